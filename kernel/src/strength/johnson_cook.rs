//! Johnson-Cook (1983) strength: `(A + B eps_p^n)(1 + C ln e*)(1 - T*^m)`, `e* = deps_p/e0`,
//! rate factor 1 for `e* < 1`. FOI (seed 001) writes the same law with letters
//! `sigma0 -> A`, `A -> B`, `B -> C`.

use super::{ComposedStrength, Hardening, ParameterBound, RateTerm, Strength, ThermalTerm};
use crate::error::ParameterError;

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

    /// Optimisation bounds, seed 000 section 4.1 (A, B in [0, 3 GPa]; n in [0, 1];
    /// C in [0, 0.1]; m in [0.5, 1.5]).
    pub const BOUNDS: [ParameterBound; 5] = [
        ParameterBound::new("yield_stress", 0.0, 3.0e9, "Pa"),
        ParameterBound::new("hardening_modulus", 0.0, 3.0e9, "Pa"),
        ParameterBound::new("hardening_exponent", 0.0, 1.0, "-"),
        ParameterBound::new("rate_sensitivity", 0.0, 0.1, "-"),
        ParameterBound::new("thermal_exponent", 0.5, 1.5, "-"),
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
