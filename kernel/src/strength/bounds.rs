//! Optimisation bounds of model constants (seed 000 section 4.1).

/// Admissible search range of one model constant, in SI units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParameterBound {
    /// Field name in the parameter struct.
    pub name: &'static str,
    /// Lower bound (SI).
    pub min: f64,
    /// Upper bound (SI).
    pub max: f64,
    /// Unit of the SI value, for reports.
    pub unit: &'static str,
}

impl ParameterBound {
    /// A bound `[min, max]` in `unit`.
    pub const fn new(name: &'static str, min: f64, max: f64, unit: &'static str) -> Self {
        Self {
            name,
            min,
            max,
            unit,
        }
    }
}
