//! Johnson-Cook (1983) strength: `(A + B eps_p^n)(1 + C ln e*)(1 - T*^m)`, `e* = deps_p/e0`,
//! rate factor 1 for `e* < 1`. FOI (seed 001) writes the same law with letters
//! `sigma0 -> A`, `A -> B`, `B -> C`.

use super::{ComposedStrength, Hardening, RateTerm, Strength, ThermalTerm};
use crate::error::ParameterError;
use crate::parameters::{self, ConstantPaths, Constants};

/// Johnson-Cook constants (SI).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct JohnsonCook {
    /// Yield stress `A` (Pa).
    pub yield_stress: f64,
    /// Hardening modulus `B` (Pa).
    pub hardening_modulus: f64,
    /// Hardening exponent `n` (-).
    pub hardening_exponent: f64,
    /// Rate sensitivity `C` (-).
    pub rate_sensitivity: f64,
    /// Thermal-softening exponent `m` (-).
    pub thermal_exponent: f64,
    /// Reference rate `e0` (1/s).
    pub reference_rate: f64,
    /// Reference temperature `Tr` (K).
    pub reference_temperature: f64,
    /// Melting temperature `Tm` (K).
    pub melting_temperature: f64,
}

impl JohnsonCook {
    /// 4340 steel, Johnson & Cook (1985): A 792 MPa, B 510 MPa, n 0.26, C 0.014, m 1.03,
    /// Tr 298 K, Tm 1793 K, e0 1 /s.
    pub const STEEL_4340: JohnsonCook = JohnsonCook {
        yield_stress: 792.0e6,
        hardening_modulus: 510.0e6,
        hardening_exponent: 0.26,
        rate_sensitivity: 0.014,
        thermal_exponent: 1.03,
        reference_rate: 1.0,
        reference_temperature: 298.0,
        melting_temperature: 1793.0,
    };

    /// High-nitrogen steel, seed 001 table 3.2 (FOI letters sigma0 699 MPa, A 1148 MPa,
    /// n 0.595, B 0.030, m 0.65), Tm 1793 K.
    pub const HNS_FOI: JohnsonCook = JohnsonCook {
        yield_stress: 699.0e6,
        hardening_modulus: 1148.0e6,
        hardening_exponent: 0.595,
        rate_sensitivity: 0.030,
        thermal_exponent: 0.65,
        reference_rate: 1.0,
        reference_temperature: 293.0,
        melting_temperature: 1793.0,
    };

    /// The composed-term path of each constant, in the order of
    /// [`parameters`](crate::parameters::Constants::parameters):
    /// where [`JohnsonCook::composed`] puts it, so that a physics term can be added to a
    /// Johnson-Cook fit without renaming its constants.
    pub const COMPOSED_PATHS: [&'static str; 8] = [
        "hardening.yield_stress",
        "hardening.hardening_modulus",
        "hardening.exponent",
        "rate.rate_sensitivity",
        "thermal.exponent",
        "rate.reference_rate",
        "thermal.reference_temperature",
        "thermal.melting_temperature",
    ];

    /// The composed form of this model.
    pub const fn composed(&self) -> ComposedStrength {
        ComposedStrength {
            hardening: Hardening::Power {
                yield_stress: self.yield_stress,
                hardening_modulus: self.hardening_modulus,
                exponent: self.hardening_exponent,
            },
            rate: RateTerm::JohnsonCookLog {
                rate_sensitivity: self.rate_sensitivity,
                reference_rate: self.reference_rate,
            },
            thermal: ThermalTerm::HomologousPower {
                exponent: self.thermal_exponent,
                reference_temperature: self.reference_temperature,
                melting_temperature: self.melting_temperature,
            },
        }
    }

    /// The Johnson-Cook model a composed strength is, if its terms are Johnson-Cook's (power
    /// hardening, JC log rate, homologous-power thermal term): the inverse of
    /// [`JohnsonCook::composed`], each constant read from its [`JohnsonCook::COMPOSED_PATHS`]
    /// entry.
    pub fn from_composed(composed: &ComposedStrength) -> Option<JohnsonCook> {
        let johnson_cook_form = matches!(
            (&composed.hardening, &composed.rate, &composed.thermal),
            (
                Hardening::Power { .. },
                RateTerm::JohnsonCookLog { .. },
                ThermalTerm::HomologousPower { .. }
            )
        );
        if !johnson_cook_form {
            return None;
        }
        let mut model = JohnsonCook::STEEL_4340;
        for (index, path) in Self::COMPOSED_PATHS.iter().enumerate() {
            *model.slot(index)? = composed.get(path)?;
        }
        Some(model)
    }

    /// Reject non-physical constants (same rules as the composed terms).
    pub fn validate(&self) -> Result<(), ParameterError> {
        self.composed().validate()
    }
}

impl From<JohnsonCook> for Strength {
    fn from(model: JohnsonCook) -> Self {
        Strength::Composed(model.composed())
    }
}

crate::struct_constants!(
    JohnsonCook,
    [
        yield_stress = ("A", "Pa", parameters::STRESS),
        hardening_modulus = ("B", "Pa", parameters::STRESS),
        hardening_exponent = ("n", "-", parameters::HARDENING_EXPONENT),
        rate_sensitivity = ("C", "-", parameters::RATE_SENSITIVITY),
        thermal_exponent = ("m", "-", parameters::THERMAL_EXPONENT),
        reference_rate = ("e0", "1/s", parameters::FIXED),
        reference_temperature = ("Tr", "K", parameters::FIXED),
        melting_temperature = ("Tm", "K", parameters::FIXED),
    ]
);
