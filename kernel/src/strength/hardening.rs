//! Strain-hardening terms `h(eps_p)`.

use crate::error::{check, ParameterError};
use crate::math::lanes::{Calls, Direct, Function, Transcendentals};
use crate::parameters;

use super::TermValue;

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

/// `B eps^n` and its first three derivatives. At `eps = 0` with `n < 1` the slope is
/// unbounded; it is returned as `+inf` (the return mapping falls back to bisection there), and
/// the higher derivatives at `eps = 0` as `+inf` unless the term is linear or constant.
#[inline]
pub(crate) fn power_term(modulus: f64, exponent: f64, plastic_strain: f64) -> TermValue {
    power_term_with(modulus, exponent, plastic_strain, &mut Direct)
}

/// Announce the call [`power_term_with`] makes at `plastic_strain` (see [`Calls`]):
/// `pow(eps, n)`, or the harmless `pow(1, n)` where the term takes no power (`eps <= 0`).
#[inline(always)]
pub(crate) fn announce_power_term(exponent: f64, plastic_strain: f64, calls: &mut Calls) {
    let x = if plastic_strain > 0.0 {
        plastic_strain
    } else {
        1.0
    };
    calls.push(Function::Pow, x, exponent);
}

/// [`power_term`] with its `pow` from `math`.
#[inline(always)]
pub(crate) fn power_term_with(
    modulus: f64,
    exponent: f64,
    plastic_strain: f64,
    math: &mut impl Transcendentals,
) -> TermValue {
    if modulus == 0.0 {
        return TermValue::CONSTANT_ZERO;
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
        let higher = if exponent == 0.0 || exponent == 1.0 {
            0.0
        } else {
            f64::INFINITY
        };
        return TermValue {
            value,
            slope,
            curvature: higher,
            third: higher,
        };
    }
    let powered = math.pow(plastic_strain, exponent);
    let inverse = 1.0 / plastic_strain;
    let slope = modulus * exponent * powered * inverse;
    // B n (n - 1) eps^(n - 2) and B n (n - 1)(n - 2) eps^(n - 3).
    let curvature = slope * (exponent - 1.0) * inverse;
    TermValue {
        value: modulus * powered,
        slope,
        curvature,
        third: curvature * (exponent - 2.0) * inverse,
    }
}

/// `Q (1 - exp(-c eps))` and its first three derivatives.
#[inline]
fn voce_term(
    saturation: f64,
    rate: f64,
    plastic_strain: f64,
    math: &mut impl Transcendentals,
) -> TermValue {
    if saturation == 0.0 {
        return TermValue::CONSTANT_ZERO;
    }
    let decay = math.exp(-rate * plastic_strain);
    let slope = saturation * rate * decay;
    let curvature = -rate * slope;
    TermValue {
        value: saturation * (1.0 - decay),
        slope,
        curvature,
        third: -rate * curvature,
    }
}

impl Hardening {
    /// `h(eps_p)` and its first three derivatives.
    #[inline]
    pub fn evaluate(&self, plastic_strain: f64) -> TermValue {
        self.evaluate_with(plastic_strain, &mut Direct)
    }

    /// [`Hardening::evaluate`] with its `pow` and `exp` from `math`.
    #[inline(always)]
    pub fn evaluate_with(&self, plastic_strain: f64, math: &mut impl Transcendentals) -> TermValue {
        match *self {
            Hardening::Power {
                yield_stress,
                hardening_modulus,
                exponent,
            } => power_term_with(hardening_modulus, exponent, plastic_strain, math)
                .plus(yield_stress),
            Hardening::Voce2 {
                yield_stress,
                saturation_stress_1,
                saturation_rate_1,
                saturation_stress_2,
                saturation_rate_2,
            } => {
                let first = voce_term(saturation_stress_1, saturation_rate_1, plastic_strain, math);
                let second =
                    voce_term(saturation_stress_2, saturation_rate_2, plastic_strain, math);
                first.plus(yield_stress).sum(&second)
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
                let power = power_term_with(hardening_modulus, exponent, plastic_strain, math);
                let first = voce_term(saturation_stress_1, saturation_rate_1, plastic_strain, math);
                let second =
                    voce_term(saturation_stress_2, saturation_rate_2, plastic_strain, math);
                power.plus(yield_stress).sum(&first).sum(&second)
            }
        }
    }

    /// Announce the calls [`Hardening::evaluate_with`] makes at `plastic_strain` (see
    /// [`Calls`]): `pow(eps, n)` of a power term, `exp(-c eps)` of each Voce term.
    #[inline(always)]
    pub fn announce(&self, plastic_strain: f64, calls: &mut Calls) {
        match *self {
            Hardening::Power { exponent, .. } => {
                announce_power_term(exponent, plastic_strain, calls);
            }
            Hardening::Voce2 {
                saturation_rate_1,
                saturation_rate_2,
                ..
            } => {
                calls.push(Function::Exp, -saturation_rate_1 * plastic_strain, 1.0);
                calls.push(Function::Exp, -saturation_rate_2 * plastic_strain, 1.0);
            }
            Hardening::PowerVoce2 {
                exponent,
                saturation_rate_1,
                saturation_rate_2,
                ..
            } => {
                announce_power_term(exponent, plastic_strain, calls);
                calls.push(Function::Exp, -saturation_rate_1 * plastic_strain, 1.0);
                calls.push(Function::Exp, -saturation_rate_2 * plastic_strain, 1.0);
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
