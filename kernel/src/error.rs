//! Typed errors of the kernel.

/// A parameter that `validate()` rejected: which model, which field, and why.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ParameterError {
    /// The field is NaN or infinite.
    NotFinite {
        /// Field name as in the parameter struct.
        field: &'static str,
    },
    /// The field must be strictly positive.
    NotPositive {
        /// Field name.
        field: &'static str,
        /// Value given.
        value: f64,
    },
    /// The field must be zero or positive.
    Negative {
        /// Field name.
        field: &'static str,
        /// Value given.
        value: f64,
    },
    /// The field is outside its physical range `[min, max]`.
    OutOfRange {
        /// Field name.
        field: &'static str,
        /// Value given.
        value: f64,
        /// Smallest admissible value.
        min: f64,
        /// Largest admissible value.
        max: f64,
    },
    /// Two fields are inconsistent with each other (e.g. melting below reference temperature).
    Inconsistent {
        /// First field.
        field: &'static str,
        /// The field it conflicts with.
        other: &'static str,
    },
}

impl core::fmt::Display for ParameterError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            ParameterError::NotFinite { field } => write!(f, "{field}: value is not finite"),
            ParameterError::NotPositive { field, value } => {
                write!(f, "{field}: must be > 0, got {value}")
            }
            ParameterError::Negative { field, value } => {
                write!(f, "{field}: must be >= 0, got {value}")
            }
            ParameterError::OutOfRange {
                field,
                value,
                min,
                max,
            } => write!(f, "{field}: {value} is outside [{min}, {max}]"),
            ParameterError::Inconsistent { field, other } => {
                write!(f, "{field}: inconsistent with {other}")
            }
        }
    }
}

impl core::error::Error for ParameterError {}

/// Why a stress update could not be carried out. The state is left unchanged when one of
/// these is returned.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum UpdateError {
    /// A strain increment component, `dt` or the relative volume is NaN or infinite.
    NonFiniteInput,
    /// `dt` is zero or negative.
    NonPositiveTimeStep,
    /// The relative volume `V/V0` is zero or negative (inverted element).
    NonPositiveVolume,
    /// The incoming state holds NaN or infinite values.
    NonFiniteState,
    /// The return-mapping iteration did not converge within its bound.
    ReturnMappingDiverged,
    /// A computed quantity became non-finite (overflow).
    NonFiniteResult,
    /// The incoming state holds a value no update can produce (negative plastic strain,
    /// temperature <= 0 K, damage outside [0, 1], ...): `variable` names it
    /// ([`crate::MaterialState::CHECKED_VARIABLES`]), `value` is what was passed.
    InadmissibleState {
        /// The state variable.
        variable: &'static crate::state::StateVariable,
        /// Its value.
        value: f64,
    },
}

impl core::fmt::Display for UpdateError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let text = match self {
            UpdateError::NonFiniteInput => "strain increment, dt or relative volume is not finite",
            UpdateError::NonPositiveTimeStep => "time step dt must be > 0",
            UpdateError::NonPositiveVolume => "relative volume V/V0 must be > 0",
            UpdateError::NonFiniteState => "incoming material state is not finite",
            UpdateError::ReturnMappingDiverged => "return mapping did not converge",
            UpdateError::NonFiniteResult => "update produced a non-finite result",
            UpdateError::InadmissibleState { variable, value } => {
                let open = if variable.lower_excluded { "(" } else { "[" };
                return write!(
                    f,
                    "incoming state.{} = {value} is outside its valid range {open}{}, {}] {}",
                    variable.name, variable.lower, variable.upper, variable.unit
                );
            }
        };
        f.write_str(text)
    }
}

impl core::error::Error for UpdateError {}

/// Helpers shared by every `validate()`.
pub(crate) mod check {
    use super::ParameterError;

    pub fn finite(field: &'static str, value: f64) -> Result<(), ParameterError> {
        if value.is_finite() {
            Ok(())
        } else {
            Err(ParameterError::NotFinite { field })
        }
    }

    pub fn positive(field: &'static str, value: f64) -> Result<(), ParameterError> {
        finite(field, value)?;
        if value > 0.0 {
            Ok(())
        } else {
            Err(ParameterError::NotPositive { field, value })
        }
    }

    pub fn non_negative(field: &'static str, value: f64) -> Result<(), ParameterError> {
        finite(field, value)?;
        if value >= 0.0 {
            Ok(())
        } else {
            Err(ParameterError::Negative { field, value })
        }
    }

    pub fn range(
        field: &'static str,
        value: f64,
        min: f64,
        max: f64,
    ) -> Result<(), ParameterError> {
        finite(field, value)?;
        if value >= min && value <= max {
            Ok(())
        } else {
            Err(ParameterError::OutOfRange {
                field,
                value,
                min,
                max,
            })
        }
    }
}
