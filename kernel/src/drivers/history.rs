//! Driver output records and where they go.

use crate::error::{ParameterError, UpdateError};
use crate::point_model::StepOutput;
use crate::state::MaterialState;
use crate::tensor::Sym;

/// The state of the point after one driver step.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Record {
    /// Time at the end of the step (s).
    pub time: f64,
    /// Accumulated logarithmic strain, Voigt, tensor shear.
    pub strain: Sym,
    /// Cauchy stress (Pa).
    pub stress: Sym,
    /// Equivalent plastic strain.
    pub plastic_strain: f64,
    /// Equivalent plastic strain rate (1/s).
    pub plastic_strain_rate: f64,
    /// Temperature (K).
    pub temperature: f64,
    /// Damage.
    pub damage: f64,
    /// Pressure (Pa), positive in compression.
    pub pressure: f64,
    /// von Mises stress (Pa).
    pub equivalent_stress: f64,
    /// Internal energy per reference volume (J/m^3).
    pub internal_energy: f64,
    /// Flow stress used in the step (Pa).
    pub yield_stress: f64,
    /// Longitudinal wave speed (m/s).
    pub wave_speed: f64,
    /// State flags after the step.
    pub flags: u32,
}

impl Record {
    /// Number of `f64` values in [`Record::values`].
    pub const VALUE_COUNT: usize = 23;

    /// Names of the values, in the order of [`Record::values`].
    pub const VALUE_NAMES: [&'static str; Record::VALUE_COUNT] = [
        "time",
        "strain_xx",
        "strain_yy",
        "strain_zz",
        "strain_xy",
        "strain_yz",
        "strain_zx",
        "stress_xx",
        "stress_yy",
        "stress_zz",
        "stress_xy",
        "stress_yz",
        "stress_zx",
        "plastic_strain",
        "plastic_strain_rate",
        "temperature",
        "damage",
        "pressure",
        "equivalent_stress",
        "internal_energy",
        "yield_stress",
        "wave_speed",
        "flags",
    ];

    /// Build a record from the state after a step.
    pub fn new(time: f64, strain: &Sym, state: &MaterialState, output: &StepOutput) -> Self {
        Self {
            time,
            strain: *strain,
            stress: state.stress,
            plastic_strain: state.plastic_strain,
            plastic_strain_rate: state.plastic_strain_rate,
            temperature: state.temperature,
            damage: state.damage,
            pressure: state.pressure(),
            equivalent_stress: state.equivalent_stress(),
            internal_energy: state.internal_energy,
            yield_stress: output.yield_stress,
            wave_speed: output.wave_speed,
            flags: state.flags.0,
        }
    }

    /// All values as `f64` (flags converted exactly), for golden files and tables.
    pub fn values(&self) -> [f64; Record::VALUE_COUNT] {
        let s = &self.strain;
        let t = &self.stress;
        [
            self.time,
            s[0],
            s[1],
            s[2],
            s[3],
            s[4],
            s[5],
            t[0],
            t[1],
            t[2],
            t[3],
            t[4],
            t[5],
            self.plastic_strain,
            self.plastic_strain_rate,
            self.temperature,
            self.damage,
            self.pressure,
            self.equivalent_stress,
            self.internal_energy,
            self.yield_stress,
            self.wave_speed,
            f64::from(self.flags),
        ]
    }
}

/// Why a driver stopped.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DriverError {
    /// The material parameters are invalid.
    Parameter(ParameterError),
    /// The stress update failed.
    Update(UpdateError),
    /// The history buffer is full.
    BufferFull,
    /// A loading parameter is not finite or not positive.
    InvalidLoading {
        /// The offending field.
        field: &'static str,
    },
    /// The lateral-stress iteration of the uniaxial-stress driver did not converge.
    LateralIterationDiverged,
}

impl core::fmt::Display for DriverError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            DriverError::Parameter(error) => write!(f, "invalid material: {error}"),
            DriverError::Update(error) => write!(f, "stress update failed: {error}"),
            DriverError::BufferFull => f.write_str("history buffer is full"),
            DriverError::InvalidLoading { field } => {
                write!(f, "loading field {field} must be finite and > 0")
            }
            DriverError::LateralIterationDiverged => {
                f.write_str("uniaxial-stress lateral iteration did not converge")
            }
        }
    }
}

impl core::error::Error for DriverError {
    /// The parameter or update error a driver failed on.
    fn source(&self) -> Option<&(dyn core::error::Error + 'static)> {
        match self {
            DriverError::Parameter(error) => Some(error),
            DriverError::Update(error) => Some(error),
            _ => None,
        }
    }
}

/// Where a driver writes its records.
pub trait HistorySink {
    /// Append one record; [`DriverError::BufferFull`] when there is no room.
    fn push(&mut self, record: Record) -> Result<(), DriverError>;
}

impl<const N: usize> HistorySink for heapless::Vec<Record, N> {
    fn push(&mut self, record: Record) -> Result<(), DriverError> {
        heapless::Vec::push(self, record).map_err(|_| DriverError::BufferFull)
    }
}

/// A caller-provided slice filled from the front.
pub struct SliceSink<'a> {
    buffer: &'a mut [Record],
    len: usize,
}

impl<'a> SliceSink<'a> {
    /// Wrap an output buffer.
    pub fn new(buffer: &'a mut [Record]) -> Self {
        Self { buffer, len: 0 }
    }

    /// Records written so far.
    pub fn len(&self) -> usize {
        self.len
    }

    /// `true` if nothing was written.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The written records.
    pub fn records(&self) -> &[Record] {
        &self.buffer[..self.len]
    }
}

impl HistorySink for SliceSink<'_> {
    fn push(&mut self, record: Record) -> Result<(), DriverError> {
        let slot = self
            .buffer
            .get_mut(self.len)
            .ok_or(DriverError::BufferFull)?;
        *slot = record;
        self.len += 1;
        Ok(())
    }
}

/// A sink that keeps only the count and the last record (for long runs and benchmarks).
#[derive(Default)]
pub struct LastRecord {
    /// Records pushed.
    pub count: usize,
    /// The most recent record.
    pub last: Option<Record>,
}

impl HistorySink for LastRecord {
    fn push(&mut self, record: Record) -> Result<(), DriverError> {
        self.count += 1;
        self.last = Some(record);
        Ok(())
    }
}
