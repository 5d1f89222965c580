//! Status codes of the C ABI and the error type that carries them to the boundary.
//!
//! The numbers are part of the ABI: a number, once given a meaning, is never reused for
//! another. New conditions get new numbers at the end.

use std::fmt;

use stoss_kernel::{ParameterError, UpdateError};

/// Result of every exported function, and of every point in a batch.
///
/// `STOSS_STATUS_OK` (0) is success; every other value names one failure. The numbers are
/// fixed forever (never renumbered, never reused).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StossStatus {
    /// Success.
    Ok = 0,
    /// A required pointer argument (or a required array inside an argument struct) is NULL.
    NullPointer = 1,
    /// A Rust panic was caught at the boundary (a bug in stoss: please report it). The
    /// outputs of the call are unspecified; no state was committed for the point that panicked.
    Panic = 2,
    /// `StossMaterialBlock::layout_version` (or card slot P1) is not the version this library
    /// was built for.
    BadLayoutVersion = 3,
    /// A material constant is invalid (the message names the field).
    InvalidParameter = 4,
    /// A strain increment component, `dt` or a relative volume is NaN or infinite.
    NonFiniteInput = 5,
    /// `dt <= 0`.
    NonPositiveTimeStep = 6,
    /// A relative volume `V/V0 <= 0` (inverted element).
    NonPositiveVolume = 7,
    /// The return mapping did not converge within its iteration bound.
    ReturnMappingDiverged = 8,
    /// A batch call with zero points.
    ZeroPoints = 9,
    /// An output buffer (card, history array, state-variable array) is too small.
    BufferTooSmall = 10,
    /// `StossMaterialBlock::struct_size` is not `sizeof(StossMaterialBlock)` of this library.
    BadStructSize = 11,
    /// The incoming state of a point holds NaN/inf or a non-positive relative volume.
    NonFiniteState = 12,
    /// The update produced a non-finite value (overflow); the state was not changed.
    NonFiniteResult = 13,
    /// A non-pointer argument is out of its domain (e.g. `ndir`, `nshr` of the VUMAT adapter).
    InvalidArgument = 14,
    /// A pointer argument is not aligned for its element type.
    MisalignedPointer = 15,
    /// The incoming state of a point holds a finite value no update can produce: negative
    /// plastic strain or rate, temperature <= 0 K, damage outside [0, 1] (the message names
    /// the point, the variable and its value).
    InadmissibleState = 16,
}

impl StossStatus {
    /// Every status, in numerical order (for tables and tests).
    pub const ALL: [StossStatus; 17] = [
        StossStatus::Ok,
        StossStatus::NullPointer,
        StossStatus::Panic,
        StossStatus::BadLayoutVersion,
        StossStatus::InvalidParameter,
        StossStatus::NonFiniteInput,
        StossStatus::NonPositiveTimeStep,
        StossStatus::NonPositiveVolume,
        StossStatus::ReturnMappingDiverged,
        StossStatus::ZeroPoints,
        StossStatus::BufferTooSmall,
        StossStatus::BadStructSize,
        StossStatus::NonFiniteState,
        StossStatus::NonFiniteResult,
        StossStatus::InvalidArgument,
        StossStatus::MisalignedPointer,
        StossStatus::InadmissibleState,
    ];

    /// The C name of the status, e.g. `"STOSS_STATUS_NULL_POINTER"` (a static string).
    pub fn name(self) -> &'static str {
        match self {
            StossStatus::Ok => "STOSS_STATUS_OK",
            StossStatus::NullPointer => "STOSS_STATUS_NULL_POINTER",
            StossStatus::Panic => "STOSS_STATUS_PANIC",
            StossStatus::BadLayoutVersion => "STOSS_STATUS_BAD_LAYOUT_VERSION",
            StossStatus::InvalidParameter => "STOSS_STATUS_INVALID_PARAMETER",
            StossStatus::NonFiniteInput => "STOSS_STATUS_NON_FINITE_INPUT",
            StossStatus::NonPositiveTimeStep => "STOSS_STATUS_NON_POSITIVE_TIME_STEP",
            StossStatus::NonPositiveVolume => "STOSS_STATUS_NON_POSITIVE_VOLUME",
            StossStatus::ReturnMappingDiverged => "STOSS_STATUS_RETURN_MAPPING_DIVERGED",
            StossStatus::ZeroPoints => "STOSS_STATUS_ZERO_POINTS",
            StossStatus::BufferTooSmall => "STOSS_STATUS_BUFFER_TOO_SMALL",
            StossStatus::BadStructSize => "STOSS_STATUS_BAD_STRUCT_SIZE",
            StossStatus::NonFiniteState => "STOSS_STATUS_NON_FINITE_STATE",
            StossStatus::NonFiniteResult => "STOSS_STATUS_NON_FINITE_RESULT",
            StossStatus::InvalidArgument => "STOSS_STATUS_INVALID_ARGUMENT",
            StossStatus::MisalignedPointer => "STOSS_STATUS_MISALIGNED_POINTER",
            StossStatus::InadmissibleState => "STOSS_STATUS_INADMISSIBLE_STATE",
        }
    }

    /// The status with numerical value `code`, if there is one.
    pub fn from_code(code: i32) -> Option<StossStatus> {
        StossStatus::ALL.iter().copied().find(|s| *s as i32 == code)
    }
}

impl From<UpdateError> for StossStatus {
    fn from(error: UpdateError) -> Self {
        match error {
            UpdateError::NonFiniteInput => StossStatus::NonFiniteInput,
            UpdateError::NonPositiveTimeStep => StossStatus::NonPositiveTimeStep,
            UpdateError::NonPositiveVolume => StossStatus::NonPositiveVolume,
            UpdateError::NonFiniteState => StossStatus::NonFiniteState,
            UpdateError::ReturnMappingDiverged => StossStatus::ReturnMappingDiverged,
            UpdateError::NonFiniteResult => StossStatus::NonFiniteResult,
            UpdateError::InadmissibleState { .. } => StossStatus::InadmissibleState,
        }
    }
}

/// A failure on its way to the C boundary: a status and a human-readable message.
#[derive(Clone, Debug, PartialEq)]
pub struct FfiError {
    /// The status returned to the caller.
    pub status: StossStatus,
    /// The message written into the caller's buffer.
    pub message: String,
}

impl FfiError {
    /// An error with `status` and `message`.
    pub fn new(status: StossStatus, message: impl Into<String>) -> Self {
        Self {
            status,
            message: message.into(),
        }
    }

    /// A NULL required pointer, naming the argument.
    pub fn null(field: &str) -> Self {
        Self::new(
            StossStatus::NullPointer,
            format!("{field}: NULL pointer where an array or struct is required"),
        )
    }

    /// An invalid material constant, prefixed with the section it belongs to.
    pub fn parameter(section: &str, error: ParameterError) -> Self {
        Self::new(StossStatus::InvalidParameter, format!("{section}: {error}"))
    }

    /// A failed update of point `index`.
    pub fn update(index: usize, error: UpdateError) -> Self {
        Self::new(error.into(), format!("point {index}: {error}"))
    }
}

impl fmt::Display for FfiError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.status.name(), self.message)
    }
}

impl std::error::Error for FfiError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_the_documented_ones_and_unique() {
        for (expected, status) in StossStatus::ALL.iter().enumerate() {
            assert_eq!(*status as i32, expected as i32, "{status:?}");
            assert_eq!(StossStatus::from_code(expected as i32), Some(*status));
        }
        assert_eq!(StossStatus::from_code(17), None);
        assert_eq!(StossStatus::from_code(-1), None);
    }

    #[test]
    fn every_update_error_has_its_own_status() {
        let errors = [
            (UpdateError::NonFiniteInput, 5),
            (UpdateError::NonPositiveTimeStep, 6),
            (UpdateError::NonPositiveVolume, 7),
            (UpdateError::ReturnMappingDiverged, 8),
            (UpdateError::NonFiniteState, 12),
            (UpdateError::NonFiniteResult, 13),
            (
                UpdateError::InadmissibleState {
                    variable: &stoss_kernel::MaterialState::CHECKED_VARIABLES[2],
                    value: -5.0,
                },
                16,
            ),
        ];
        for (error, code) in errors {
            assert_eq!(StossStatus::from(error) as i32, code, "{error:?}");
        }
    }

    #[test]
    fn names_match_the_c_enumerators() {
        for status in StossStatus::ALL {
            let name = status.name();
            assert!(name.starts_with("STOSS_STATUS_"));
            let camel: String = name["STOSS_STATUS_".len()..]
                .split('_')
                .map(|w| {
                    let mut c = w.chars();
                    let first = c.next().unwrap();
                    first.to_string() + &c.as_str().to_lowercase()
                })
                .collect();
            assert_eq!(camel, format!("{status:?}"));
        }
    }
}
