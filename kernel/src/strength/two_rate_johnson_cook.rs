//! Two-part-rate Johnson-Cook (TJC, seed 000): MJC hardening and thermal terms with the rate
//! factor `(1 + deps_p/e01)^beta1 (1 + deps_p/e02)^beta2`.

use super::{ComposedStrength, Hardening, RateTerm, Strength, ThermalTerm};
use crate::error::ParameterError;
use crate::parameters;

/// TJC constants (SI).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
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
    /// The composed-term path of each constant, in the order of
    /// [`parameters`](crate::parameters::Constants::parameters).
    pub const COMPOSED_PATHS: [&'static str; 14] = [
        "hardening.yield_stress",
        "hardening.hardening_modulus",
        "hardening.exponent",
        "hardening.saturation_stress_1",
        "hardening.saturation_rate_1",
        "hardening.saturation_stress_2",
        "hardening.saturation_rate_2",
        "rate.reference_rate_1",
        "rate.exponent_1",
        "rate.reference_rate_2",
        "rate.exponent_2",
        "thermal.exponent",
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

// Seed 000 section 4.1 lost the exponents of some bounds; stoss searches Q in [0, 3 GPa],
// e01 in [1e-4, 1] /s (the quasi-static side) and e02 in [1, 1e4] /s (the dynamic side).
crate::struct_constants!(
    TwoRateJohnsonCook,
    [
        yield_stress = ("A", "Pa", parameters::STRESS),
        hardening_modulus = ("B", "Pa", parameters::STRESS),
        hardening_exponent = ("n", "-", parameters::HARDENING_EXPONENT),
        saturation_stress_1 = ("Q1", "Pa", parameters::STRESS),
        saturation_rate_1 = ("c1", "-", parameters::SATURATION_RATE),
        saturation_stress_2 = ("Q2", "Pa", parameters::STRESS),
        saturation_rate_2 = ("c2", "-", parameters::SATURATION_RATE),
        reference_rate_1 = ("e01", "1/s", Some((1.0e-4, 1.0))),
        rate_exponent_1 = ("beta1", "-", parameters::RATE_SENSITIVITY),
        reference_rate_2 = ("e02", "1/s", Some((1.0, 1.0e4))),
        rate_exponent_2 = ("beta2", "-", parameters::RATE_SENSITIVITY),
        thermal_exponent = ("m", "-", parameters::THERMAL_EXPONENT),
        reference_temperature = ("Tr", "K", parameters::FIXED),
        melting_temperature = ("Tm", "K", parameters::FIXED),
    ]
);
