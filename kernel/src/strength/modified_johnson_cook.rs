//! Modified Johnson-Cook (MJC, seed 000): power plus two Voce hardening terms, power-law rate
//! `(1 + e*)^beta`, JC thermal softening:
//! `(A + B eps^n + Q1(1-exp(-c1 eps)) + Q2(1-exp(-c2 eps))) (1 + e*)^beta (1 - T*^m)`.

use super::{ComposedStrength, Hardening, RateTerm, Strength, ThermalTerm};
use crate::error::ParameterError;
use crate::parameters;

/// MJC constants (SI).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct ModifiedJohnsonCook {
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
    /// Rate exponent `beta` (-).
    pub rate_exponent: f64,
    /// Reference rate `e0` (1/s).
    pub reference_rate: f64,
    /// Thermal exponent `m` (-).
    pub thermal_exponent: f64,
    /// Reference temperature `Tr` (K).
    pub reference_temperature: f64,
    /// Melting temperature `Tm` (K).
    pub melting_temperature: f64,
}

impl ModifiedJohnsonCook {
    /// The composed-term path of each constant, in the order of
    /// [`parameters`](crate::parameters::Constants::parameters).
    pub const COMPOSED_PATHS: [&'static str; 12] = [
        "hardening.yield_stress",
        "hardening.hardening_modulus",
        "hardening.exponent",
        "hardening.saturation_stress_1",
        "hardening.saturation_rate_1",
        "hardening.saturation_stress_2",
        "hardening.saturation_rate_2",
        "rate.exponent",
        "thermal.exponent",
        "rate.reference_rate",
        "thermal.reference_temperature",
        "thermal.melting_temperature",
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
            rate: RateTerm::Power {
                exponent: self.rate_exponent,
                reference_rate: self.reference_rate,
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
        self.composed().validate()
    }
}

impl From<ModifiedJohnsonCook> for Strength {
    fn from(model: ModifiedJohnsonCook) -> Self {
        Strength::Composed(model.composed())
    }
}

crate::struct_constants!(
    ModifiedJohnsonCook,
    [
        yield_stress = ("A", "Pa", parameters::STRESS),
        hardening_modulus = ("B", "Pa", parameters::STRESS),
        hardening_exponent = ("n", "-", parameters::HARDENING_EXPONENT),
        saturation_stress_1 = ("Q1", "Pa", parameters::STRESS),
        saturation_rate_1 = ("c1", "-", parameters::SATURATION_RATE),
        saturation_stress_2 = ("Q2", "Pa", parameters::STRESS),
        saturation_rate_2 = ("c2", "-", parameters::SATURATION_RATE),
        rate_exponent = ("beta", "-", parameters::RATE_SENSITIVITY),
        thermal_exponent = ("m", "-", parameters::THERMAL_EXPONENT),
        reference_rate = ("e0", "1/s", parameters::FIXED),
        reference_temperature = ("Tr", "K", parameters::FIXED),
        melting_temperature = ("Tm", "K", parameters::FIXED),
    ]
);
