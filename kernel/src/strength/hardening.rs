//! Strain-hardening terms `h(eps_p)`.

use crate::error::{check, ParameterError};
use crate::math::{exp, pow};
use crate::parameters;

/// Isotropic strain hardening as a function of equivalent plastic strain.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "kebab-case"))]
pub enum Hardening {
    /// Power law (Ludwik, JC first bracket): `A + B eps_p^n`.
    Power {
        /// Initial yield stress `A` (Pa).
        yield_stress: f64,
        /// Hardening modulus `B` (Pa).
        hardening_modulus: f64,
        /// Hardening exponent `n` (-).
        exponent: f64,
    },
    /// Two-term Voce saturation: `A + Q1 (1 - exp(-c1 eps_p)) + Q2 (1 - exp(-c2 eps_p))`.
    Voce2 {
        /// Initial yield stress `A` (Pa).
        yield_stress: f64,
        /// First saturation stress `Q1` (Pa).
        saturation_stress_1: f64,
        /// First saturation rate `c1` (-).
        saturation_rate_1: f64,
        /// Second saturation stress `Q2` (Pa).
        saturation_stress_2: f64,
        /// Second saturation rate `c2` (-).
        saturation_rate_2: f64,
    },
    /// Power law plus two Voce terms (MJC/TJC of seed 000):
    /// `A + B eps_p^n + Q1 (1 - exp(-c1 eps_p)) + Q2 (1 - exp(-c2 eps_p))`.
    PowerVoce2 {
        /// Initial yield stress `A` (Pa).
        yield_stress: f64,
        /// Hardening modulus `B` (Pa).
        hardening_modulus: f64,
        /// Hardening exponent `n` (-).
        exponent: f64,
        /// First saturation stress `Q1` (Pa).
        saturation_stress_1: f64,
        /// First saturation rate `c1` (-).
        saturation_rate_1: f64,
        /// Second saturation stress `Q2` (Pa).
        saturation_stress_2: f64,
        /// Second saturation rate `c2` (-).
        saturation_rate_2: f64,
    },
}

/// `B eps^n` and its derivative. At `eps = 0` with `n < 1` the derivative is unbounded; it is
/// returned as `+inf` and the return mapping falls back to bisection there.
#[inline]
fn power_term(modulus: f64, exponent: f64, plastic_strain: f64) -> (f64, f64) {
    if modulus == 0.0 {
        return (0.0, 0.0);
    }
    if plastic_strain <= 0.0 {
        let slope = if exponent == 0.0 {
            0.0
        } else if exponent < 1.0 {
            f64::INFINITY
        } else if exponent == 1.0 {
            modulus
        } else {
            0.0
        };
        let value = if exponent == 0.0 { modulus } else { 0.0 };
        return (value, slope);
    }
    let powered = pow(plastic_strain, exponent);
    (
        modulus * powered,
        modulus * exponent * powered / plastic_strain,
    )
}

/// `Q (1 - exp(-c eps))` and its derivative.
#[inline]
fn voce_term(saturation: f64, rate: f64, plastic_strain: f64) -> (f64, f64) {
    if saturation == 0.0 {
        return (0.0, 0.0);
    }
    let decay = exp(-rate * plastic_strain);
    (saturation * (1.0 - decay), saturation * rate * decay)
}

impl Hardening {
    /// `h(eps_p)` and `dh/deps_p`.
    #[inline]
    pub fn evaluate(&self, plastic_strain: f64) -> (f64, f64) {
        match *self {
            Hardening::Power {
                yield_stress,
                hardening_modulus,
                exponent,
            } => {
                let (value, slope) = power_term(hardening_modulus, exponent, plastic_strain);
                (yield_stress + value, slope)
            }
            Hardening::Voce2 {
                yield_stress,
                saturation_stress_1,
                saturation_rate_1,
                saturation_stress_2,
                saturation_rate_2,
            } => {
                let (v1, s1) = voce_term(saturation_stress_1, saturation_rate_1, plastic_strain);
                let (v2, s2) = voce_term(saturation_stress_2, saturation_rate_2, plastic_strain);
                (yield_stress + v1 + v2, s1 + s2)
            }
            Hardening::PowerVoce2 {
                yield_stress,
                hardening_modulus,
                exponent,
                saturation_stress_1,
                saturation_rate_1,
                saturation_stress_2,
                saturation_rate_2,
            } => {
                let (vp, sp) = power_term(hardening_modulus, exponent, plastic_strain);
                let (v1, s1) = voce_term(saturation_stress_1, saturation_rate_1, plastic_strain);
                let (v2, s2) = voce_term(saturation_stress_2, saturation_rate_2, plastic_strain);
                (yield_stress + vp + v1 + v2, sp + s1 + s2)
            }
        }
    }

    /// Reject non-physical constants: stresses and rates must be finite and non-negative
    /// (softening hardening terms are not supported), `A > 0`.
    pub fn validate(&self) -> Result<(), ParameterError> {
        match *self {
            Hardening::Power {
                yield_stress,
                hardening_modulus,
                exponent,
            } => {
                check::positive("yield_stress", yield_stress)?;
                check::non_negative("hardening_modulus", hardening_modulus)?;
                check::range("hardening_exponent", exponent, 0.0, 2.0)
            }
            Hardening::Voce2 {
                yield_stress,
                saturation_stress_1,
                saturation_rate_1,
                saturation_stress_2,
                saturation_rate_2,
            } => {
                check::positive("yield_stress", yield_stress)?;
                check::non_negative("saturation_stress_1", saturation_stress_1)?;
                check::non_negative("saturation_rate_1", saturation_rate_1)?;
                check::non_negative("saturation_stress_2", saturation_stress_2)?;
                check::non_negative("saturation_rate_2", saturation_rate_2)
            }
            Hardening::PowerVoce2 {
                yield_stress,
                hardening_modulus,
                exponent,
                saturation_stress_1,
                saturation_rate_1,
                saturation_stress_2,
                saturation_rate_2,
            } => {
                check::positive("yield_stress", yield_stress)?;
                check::non_negative("hardening_modulus", hardening_modulus)?;
                check::range("hardening_exponent", exponent, 0.0, 2.0)?;
                check::non_negative("saturation_stress_1", saturation_stress_1)?;
                check::non_negative("saturation_rate_1", saturation_rate_1)?;
                check::non_negative("saturation_stress_2", saturation_stress_2)?;
                check::non_negative("saturation_rate_2", saturation_rate_2)
            }
        }
    }
}

crate::enum_constants!(Hardening, {
    Power {
        yield_stress = ("A", "Pa", parameters::STRESS),
        hardening_modulus = ("B", "Pa", parameters::STRESS),
        exponent = ("n", "-", parameters::HARDENING_EXPONENT),
    },
    Voce2 {
        yield_stress = ("A", "Pa", parameters::STRESS),
        saturation_stress_1 = ("Q1", "Pa", parameters::STRESS),
        saturation_rate_1 = ("c1", "-", parameters::SATURATION_RATE),
        saturation_stress_2 = ("Q2", "Pa", parameters::STRESS),
        saturation_rate_2 = ("c2", "-", parameters::SATURATION_RATE),
    },
    PowerVoce2 {
        yield_stress = ("A", "Pa", parameters::STRESS),
        hardening_modulus = ("B", "Pa", parameters::STRESS),
        exponent = ("n", "-", parameters::HARDENING_EXPONENT),
        saturation_stress_1 = ("Q1", "Pa", parameters::STRESS),
        saturation_rate_1 = ("c1", "-", parameters::SATURATION_RATE),
        saturation_stress_2 = ("Q2", "Pa", parameters::STRESS),
        saturation_rate_2 = ("c2", "-", parameters::SATURATION_RATE),
    },
});
