//! Two-part-rate Johnson-Cook (TJC, seed 000): MJC hardening and thermal terms with the rate
//! factor `(1 + deps_p/e01)^beta1 (1 + deps_p/e02)^beta2`.

use super::{ComposedStrength, Hardening, ParameterBound, RateTerm, Strength, ThermalTerm};
use crate::error::ParameterError;

/// TJC constants (SI).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct TwoRateJohnsonCook {
    /// Yield stress `A` (Pa).
    pub yield_stress: f64,
    /// Hardening modulus `B` (Pa).
    pub hardening_modulus: f64,
    /// Hardening exponent `n` (-).
    pub hardening_exponent: f64,
    /// First Voce saturation stress `Q1` (Pa).
    pub saturation_stress_1: f64,
    /// First Voce rate `c1` (-).
    pub saturation_rate_1: f64,
    /// Second Voce saturation stress `Q2` (Pa).
    pub saturation_stress_2: f64,
    /// Second Voce rate `c2` (-).
    pub saturation_rate_2: f64,
    /// Low-rate exponent `beta1` (-).
    pub rate_exponent_1: f64,
    /// Low-rate reference `e01` (1/s).
    pub reference_rate_1: f64,
    /// High-rate exponent `beta2` (-).
    pub rate_exponent_2: f64,
    /// High-rate reference `e02` (1/s).
    pub reference_rate_2: f64,
    /// Thermal exponent `m` (-).
    pub thermal_exponent: f64,
    /// Reference temperature `Tr` (K).
    pub reference_temperature: f64,
    /// Melting temperature `Tm` (K).
    pub melting_temperature: f64,
}

impl TwoRateJohnsonCook {
    /// Optimisation bounds, seed 000 section 4.1. Lost exponents chosen as: Q in [0, 3 GPa];
    /// e01 in [1e-4, 1] /s (quasi-static side); e02 in [1, 1e4] /s (dynamic side).
    pub const BOUNDS: [ParameterBound; 12] = [
        ParameterBound::new("yield_stress", 0.0, 3.0e9, "Pa"),
        ParameterBound::new("hardening_modulus", 0.0, 3.0e9, "Pa"),
        ParameterBound::new("hardening_exponent", 0.0, 1.0, "-"),
        ParameterBound::new("saturation_stress_1", 0.0, 3.0e9, "Pa"),
        ParameterBound::new("saturation_rate_1", 0.0, 2000.0, "-"),
        ParameterBound::new("saturation_stress_2", 0.0, 3.0e9, "Pa"),
        ParameterBound::new("saturation_rate_2", 0.0, 2000.0, "-"),
        ParameterBound::new("reference_rate_1", 1.0e-4, 1.0, "1/s"),
        ParameterBound::new("rate_exponent_1", 0.0, 0.1, "-"),
        ParameterBound::new("reference_rate_2", 1.0, 1.0e4, "1/s"),
        ParameterBound::new("rate_exponent_2", 0.0, 0.1, "-"),
        ParameterBound::new("thermal_exponent", 0.5, 1.5, "-"),
    ];

    /// The composed form of this model.
    pub const fn composed(&self) -> ComposedStrength {
        ComposedStrength {
            hardening: Hardening::PowerVoce2 {
                yield_stress: self.yield_stress,
                hardening_modulus: self.hardening_modulus,
                exponent: self.hardening_exponent,
                saturation_stress_1: self.saturation_stress_1,
                saturation_rate_1: self.saturation_rate_1,
                saturation_stress_2: self.saturation_stress_2,
                saturation_rate_2: self.saturation_rate_2,
            },
            rate: RateTerm::TwoPart {
                exponent_1: self.rate_exponent_1,
                reference_rate_1: self.reference_rate_1,
                exponent_2: self.rate_exponent_2,
                reference_rate_2: self.reference_rate_2,
            },
            thermal: ThermalTerm::HomologousPower {
                exponent: self.thermal_exponent,
                reference_temperature: self.reference_temperature,
                melting_temperature: self.melting_temperature,
            },
        }
    }

    /// Reject non-physical constants.
    pub fn validate(&self) -> Result<(), ParameterError> {
        // The rate term checks that e02 >= e01 (one home for the rule, composed models too).
        self.composed().validate()
    }
}

impl From<TwoRateJohnsonCook> for Strength {
    fn from(model: TwoRateJohnsonCook) -> Self {
        Strength::Composed(model.composed())
    }
}
