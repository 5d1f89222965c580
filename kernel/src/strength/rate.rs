//! Strain-rate terms `r(deps_p)`, each equal to 1 at zero rate (quasi-static).

use crate::error::{check, ParameterError};
use crate::math::{ln, pow};

/// Multiplicative strain-rate factor on the flow stress.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "kebab-case"))]
pub enum RateTerm {
    /// Rate-independent: `r = 1`.
    None,
    /// Johnson-Cook logarithmic: `1 + C ln(e*)` with `e* = deps_p / e0`; `r = 1` for `e* < 1`.
    JohnsonCookLog {
        /// Rate sensitivity `C` (-).
        rate_sensitivity: f64,
        /// Reference rate `e0` (1/s); stoss's JC uses 1 /s.
        reference_rate: f64,
    },
    /// Power law (MJC of seed 000, after Børvik/Camacho-Ortiz form): `(1 + deps_p/e0)^beta`.
    Power {
        /// Exponent `beta` (-).
        exponent: f64,
        /// Reference rate `e0` (1/s).
        reference_rate: f64,
    },
    /// Two-part product (TJC of seed 000):
    /// `(1 + deps_p/e01)^beta1 (1 + deps_p/e02)^beta2`.
    TwoPart {
        /// Exponent `beta1` of the low-rate part (-).
        exponent_1: f64,
        /// Reference rate `e01` of the low-rate part (1/s).
        reference_rate_1: f64,
        /// Exponent `beta2` of the high-rate part (-).
        exponent_2: f64,
        /// Reference rate `e02` of the high-rate part (1/s).
        reference_rate_2: f64,
    },
    /// Cowper-Symonds: `1 + (deps_p / D)^(1/q)`.
    CowperSymonds {
        /// Rate constant `D` (1/s).
        rate_constant: f64,
        /// Exponent `q` (-).
        exponent: f64,
    },
}

/// `(1 + rate/e0)^beta` and its derivative with respect to `rate`.
#[inline]
fn power_factor(exponent: f64, reference_rate: f64, plastic_strain_rate: f64) -> (f64, f64) {
    if exponent == 0.0 {
        return (1.0, 0.0);
    }
    let base = 1.0 + plastic_strain_rate / reference_rate;
    let value = pow(base, exponent);
    (value, exponent * value / base / reference_rate)
}

impl RateTerm {
    /// `r(deps_p)` and `dr/d deps_p` for a non-negative plastic strain rate.
    #[inline]
    pub fn evaluate(&self, plastic_strain_rate: f64) -> (f64, f64) {
        let rate = if plastic_strain_rate > 0.0 {
            plastic_strain_rate
        } else {
            0.0
        };
        match *self {
            RateTerm::None => (1.0, 0.0),
            RateTerm::JohnsonCookLog {
                rate_sensitivity,
                reference_rate,
            } => {
                let ratio = rate / reference_rate;
                if ratio <= 1.0 {
                    (1.0, 0.0)
                } else {
                    (1.0 + rate_sensitivity * ln(ratio), rate_sensitivity / rate)
                }
            }
            RateTerm::Power {
                exponent,
                reference_rate,
            } => power_factor(exponent, reference_rate, rate),
            RateTerm::TwoPart {
                exponent_1,
                reference_rate_1,
                exponent_2,
                reference_rate_2,
            } => {
                let (v1, d1) = power_factor(exponent_1, reference_rate_1, rate);
                let (v2, d2) = power_factor(exponent_2, reference_rate_2, rate);
                (v1 * v2, d1 * v2 + v1 * d2)
            }
            RateTerm::CowperSymonds {
                rate_constant,
                exponent,
            } => {
                if rate == 0.0 {
                    let slope = if exponent < 1.0 {
                        0.0
                    } else if exponent == 1.0 {
                        1.0 / rate_constant
                    } else {
                        f64::INFINITY
                    };
                    return (1.0, slope);
                }
                let powered = pow(rate / rate_constant, 1.0 / exponent);
                (1.0 + powered, powered / (exponent * rate))
            }
        }
    }

    /// Reject non-physical constants (negative sensitivities, non-positive reference rates).
    pub fn validate(&self) -> Result<(), ParameterError> {
        match *self {
            RateTerm::None => Ok(()),
            RateTerm::JohnsonCookLog {
                rate_sensitivity,
                reference_rate,
            } => {
                check::range("rate_sensitivity", rate_sensitivity, 0.0, 1.0)?;
                check::positive("reference_rate", reference_rate)
            }
            RateTerm::Power {
                exponent,
                reference_rate,
            } => {
                check::range("rate_exponent", exponent, 0.0, 1.0)?;
                check::positive("reference_rate", reference_rate)
            }
            RateTerm::TwoPart {
                exponent_1,
                reference_rate_1,
                exponent_2,
                reference_rate_2,
            } => {
                check::range("rate_exponent_1", exponent_1, 0.0, 1.0)?;
                check::positive("reference_rate_1", reference_rate_1)?;
                check::range("rate_exponent_2", exponent_2, 0.0, 1.0)?;
                check::positive("reference_rate_2", reference_rate_2)?;
                if reference_rate_2 < reference_rate_1 {
                    return Err(ParameterError::Inconsistent {
                        field: "reference_rate_2",
                        other: "reference_rate_1",
                    });
                }
                Ok(())
            }
            RateTerm::CowperSymonds {
                rate_constant,
                exponent,
            } => {
                check::positive("rate_constant", rate_constant)?;
                check::positive("cowper_symonds_exponent", exponent)
            }
        }
    }
}
