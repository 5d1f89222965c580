//! Linear EoS `p = K mu` (seed 001 table 3.2 uses it for the steels).

use super::EnergyLinearPressure;
use crate::error::{check, ParameterError};

/// Linear EoS constants.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct LinearEos {
    /// Bulk modulus `K` (Pa).
    pub bulk_modulus: f64,
}

impl LinearEos {
    /// `p = K mu`, no energy dependence.
    #[inline]
    pub fn evaluate(&self, mu: f64) -> EnergyLinearPressure {
        EnergyLinearPressure {
            base: self.bulk_modulus * mu,
            d_base_d_mu: self.bulk_modulus,
            energy_coefficient: 0.0,
            d_energy_coefficient_d_mu: 0.0,
        }
    }

    /// `K > 0`.
    pub fn validate(&self) -> Result<(), ParameterError> {
        check::positive("bulk_modulus", self.bulk_modulus)
    }
}

crate::struct_constants!(
    LinearEos,
    [bulk_modulus = ("K", "Pa", crate::parameters::FIXED)]
);
