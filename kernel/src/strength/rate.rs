//! Strain-rate terms `r(deps_p)`, each equal to 1 at zero rate (quasi-static).

use crate::error::{check, ParameterError};
use crate::math::lanes::{Calls, Direct, Function, Transcendentals};
use crate::parameters;

use super::TermValue;

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
    /// Johnson-Cook log with a high-rate upturn:
    /// `(1 + C ln e*) (1 + deps_p / e_up)^beta` (`1 + C ln e*` replaced by 1 for `e* < 1`).
    /// Nests JC exactly at `beta = 0` (the diagnosis's "high-rate upturn" term).
    LogUpturn {
        /// Rate sensitivity `C` (-).
        rate_sensitivity: f64,
        /// Reference rate `e0` (1/s).
        reference_rate: f64,
        /// Upturn exponent `beta` (-).
        upturn_exponent: f64,
        /// Rate at which the upturn sets in, `e_up` (1/s).
        upturn_rate: f64,
    },
    /// Johnson-Cook log with a temperature-dependent sensitivity (a ZA-like rate-temperature
    /// coupling): `1 + C (1 + kappa T*) ln e*`, `T*` homologous. Nests JC exactly at
    /// `kappa = 0`.
    LogThermal {
        /// Rate sensitivity `C` at the reference temperature (-).
        rate_sensitivity: f64,
        /// Reference rate `e0` (1/s).
        reference_rate: f64,
        /// Coupling `kappa` (-).
        coupling: f64,
        /// Reference temperature `Tr` (K).
        reference_temperature: f64,
        /// Melting temperature `Tm` (K).
        melting_temperature: f64,
    },
    /// Cowper-Symonds: `1 + (deps_p / D)^(1/q)`.
    CowperSymonds {
        /// Rate constant `D` (1/s).
        rate_constant: f64,
        /// Exponent `q` (-).
        exponent: f64,
    },
}

/// `(1 + rate/e0)^beta` and its first three derivatives with respect to `rate`.
#[inline]
fn power_factor(
    exponent: f64,
    reference_rate: f64,
    plastic_strain_rate: f64,
    math: &mut impl Transcendentals,
) -> TermValue {
    if exponent == 0.0 {
        return TermValue::CONSTANT_ONE;
    }
    let base = 1.0 + plastic_strain_rate / reference_rate;
    let value = math.pow(base, exponent);
    let inverse = 1.0 / (base * reference_rate);
    let slope = exponent * value * inverse;
    let curvature = slope * (exponent - 1.0) * inverse;
    TermValue {
        value,
        slope,
        curvature,
        third: curvature * (exponent - 2.0) * inverse,
    }
}

/// `1 + C ln(rate/e0)` above `e0` (1 below) and its first three derivatives; `sensitivity` is
/// `C`.
#[inline]
fn log_factor(
    sensitivity: f64,
    reference_rate: f64,
    rate: f64,
    math: &mut impl Transcendentals,
) -> TermValue {
    let ratio = rate / reference_rate;
    if ratio <= 1.0 {
        TermValue::CONSTANT_ONE
    } else {
        let inverse = 1.0 / rate;
        let slope = sensitivity * inverse;
        let curvature = -slope * inverse;
        TermValue {
            value: 1.0 + sensitivity * math.ln(ratio),
            slope,
            curvature,
            third: -2.0 * curvature * inverse,
        }
    }
}

impl RateTerm {
    /// `r(deps_p, T)` and its first three derivatives in `deps_p` for a non-negative plastic
    /// strain rate (only [`RateTerm::LogThermal`] depends on the temperature).
    #[inline]
    pub fn evaluate(&self, plastic_strain_rate: f64, temperature: f64) -> TermValue {
        self.evaluate_with(plastic_strain_rate, temperature, &mut Direct)
    }

    /// Announce the calls [`RateTerm::evaluate_with`] makes at `plastic_strain_rate` (see
    /// [`Calls`]): `ln(rate/e0)` of a logarithmic factor, `pow(1 + rate/e0, beta)` of a power
    /// factor, `pow(rate/D, 1/q)` of Cowper-Symonds.
    #[inline(always)]
    pub fn announce(&self, plastic_strain_rate: f64, calls: &mut Calls) {
        let rate = Self::floored(plastic_strain_rate);
        let log = |calls: &mut Calls, reference_rate: f64| {
            let ratio = rate / reference_rate;
            calls.push(Function::Ln, if ratio > 1.0 { ratio } else { 1.0 }, 1.0);
        };
        let power = |calls: &mut Calls, exponent: f64, reference_rate: f64| {
            calls.push(Function::Pow, 1.0 + rate / reference_rate, exponent);
        };
        match *self {
            RateTerm::None => {}
            RateTerm::JohnsonCookLog { reference_rate, .. }
            | RateTerm::LogThermal { reference_rate, .. } => log(calls, reference_rate),
            RateTerm::Power {
                exponent,
                reference_rate,
            } => power(calls, exponent, reference_rate),
            RateTerm::TwoPart {
                exponent_1,
                reference_rate_1,
                exponent_2,
                reference_rate_2,
            } => {
                power(calls, exponent_1, reference_rate_1);
                power(calls, exponent_2, reference_rate_2);
            }
            RateTerm::LogUpturn {
                reference_rate,
                upturn_exponent,
                upturn_rate,
                ..
            } => {
                log(calls, reference_rate);
                power(calls, upturn_exponent, upturn_rate);
            }
            RateTerm::CowperSymonds {
                rate_constant,
                exponent,
            } => {
                calls.push(Function::Pow, rate / rate_constant, 1.0 / exponent);
            }
        }
    }

    /// A plastic strain rate held at 0 from below.
    #[inline(always)]
    fn floored(plastic_strain_rate: f64) -> f64 {
        if plastic_strain_rate > 0.0 {
            plastic_strain_rate
        } else {
            0.0
        }
    }

    /// [`RateTerm::evaluate`] with its `ln` and `pow` from `math`.
    #[inline(always)]
    pub fn evaluate_with(
        &self,
        plastic_strain_rate: f64,
        temperature: f64,
        math: &mut impl Transcendentals,
    ) -> TermValue {
        let rate = Self::floored(plastic_strain_rate);
        match *self {
            RateTerm::None => TermValue::CONSTANT_ONE,
            RateTerm::JohnsonCookLog {
                rate_sensitivity,
                reference_rate,
            } => log_factor(rate_sensitivity, reference_rate, rate, math),
            RateTerm::Power {
                exponent,
                reference_rate,
            } => power_factor(exponent, reference_rate, rate, math),
            RateTerm::TwoPart {
                exponent_1,
                reference_rate_1,
                exponent_2,
                reference_rate_2,
            } => power_factor(exponent_1, reference_rate_1, rate, math).product(&power_factor(
                exponent_2,
                reference_rate_2,
                rate,
                math,
            )),
            RateTerm::LogUpturn {
                rate_sensitivity,
                reference_rate,
                upturn_exponent,
                upturn_rate,
            } => log_factor(rate_sensitivity, reference_rate, rate, math).product(&power_factor(
                upturn_exponent,
                upturn_rate,
                rate,
                math,
            )),
            RateTerm::LogThermal {
                rate_sensitivity,
                reference_rate,
                coupling,
                reference_temperature,
                melting_temperature,
            } => {
                if rate / reference_rate <= 1.0 {
                    TermValue::CONSTANT_ONE
                } else {
                    let t_star = super::homologous_temperature(
                        temperature,
                        reference_temperature,
                        melting_temperature,
                    );
                    let sensitivity = rate_sensitivity * (1.0 + coupling * t_star);
                    log_factor(sensitivity, reference_rate, rate, math)
                }
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
                    let higher = if exponent == 1.0 { 0.0 } else { f64::INFINITY };
                    return TermValue {
                        value: 1.0,
                        slope,
                        curvature: higher,
                        third: higher,
                    };
                }
                let powered = math.pow(rate / rate_constant, 1.0 / exponent);
                let slope = powered / (exponent * rate);
                let curvature = slope * (1.0 / exponent - 1.0) / rate;
                TermValue {
                    value: 1.0 + powered,
                    slope,
                    curvature,
                    third: curvature * (1.0 / exponent - 2.0) / rate,
                }
            }
        }
    }

    /// The plastic strain rate at which the factor changes branch (the logarithmic forms'
    /// `e0`, below which they are 1); 0 for the forms smooth at every positive rate.
    #[inline]
    pub fn kink_rate(&self) -> f64 {
        match *self {
            RateTerm::JohnsonCookLog { reference_rate, .. }
            | RateTerm::LogUpturn { reference_rate, .. }
            | RateTerm::LogThermal { reference_rate, .. } => reference_rate,
            RateTerm::None
            | RateTerm::Power { .. }
            | RateTerm::TwoPart { .. }
            | RateTerm::CowperSymonds { .. } => 0.0,
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
            RateTerm::LogUpturn {
                rate_sensitivity,
                reference_rate,
                upturn_exponent,
                upturn_rate,
            } => {
                check::range("rate_sensitivity", rate_sensitivity, 0.0, 1.0)?;
                check::positive("reference_rate", reference_rate)?;
                check::range("upturn_exponent", upturn_exponent, 0.0, 1.0)?;
                check::positive("upturn_rate", upturn_rate)
            }
            RateTerm::LogThermal {
                rate_sensitivity,
                reference_rate,
                coupling,
                reference_temperature,
                melting_temperature,
            } => {
                check::range("rate_sensitivity", rate_sensitivity, 0.0, 1.0)?;
                check::positive("reference_rate", reference_rate)?;
                check::range("coupling", coupling, -1.0, 100.0)?;
                check::positive("reference_temperature", reference_temperature)?;
                if melting_temperature <= reference_temperature {
                    return Err(ParameterError::Inconsistent {
                        field: "melting_temperature",
                        other: "reference_temperature",
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

#[cfg(test)]
mod tests {
    use super::*;

    const JC: RateTerm = RateTerm::JohnsonCookLog {
        rate_sensitivity: 0.014,
        reference_rate: 1.0,
    };

    #[test]
    fn extensions_nest_johnson_cook_exactly_at_their_null_values() {
        // GOAL: the diagnosis's candidate terms give back JC bit for bit at their null value.
        // SETUP: upturn with beta = 0, thermal coupling with kappa = 0, rates 0.1-1e5, 300-900 K.
        // REFERENCE: JohnsonCookLog, compared bit for bit (value and rate derivative).
        let upturn = RateTerm::LogUpturn {
            rate_sensitivity: 0.014,
            reference_rate: 1.0,
            upturn_exponent: 0.0,
            upturn_rate: 1.0e3,
        };
        let thermal = RateTerm::LogThermal {
            rate_sensitivity: 0.014,
            reference_rate: 1.0,
            coupling: 0.0,
            reference_temperature: 298.0,
            melting_temperature: 1793.0,
        };
        for rate in [0.1, 1.0, 10.0, 1.0e3, 1.0e5] {
            for temperature in [300.0, 900.0] {
                let reference = JC.evaluate(rate, temperature);
                for term in [upturn, thermal] {
                    let value = term.evaluate(rate, temperature);
                    assert_eq!(value.value.to_bits(), reference.value.to_bits());
                    assert_eq!(value.slope.to_bits(), reference.slope.to_bits());
                    assert_eq!(value.curvature.to_bits(), reference.curvature.to_bits());
                    assert_eq!(value.third.to_bits(), reference.third.to_bits());
                }
            }
        }
    }

    #[test]
    fn extension_rate_derivatives_match_central_differences() {
        // GOAL: analytic d r / d rate of the new terms. SETUP: beta 0.05, kappa 2, 5e3 /s, 600 K.
        // REFERENCE: central differences, relative 1e-6.
        let terms = [
            RateTerm::LogUpturn {
                rate_sensitivity: 0.014,
                reference_rate: 1.0,
                upturn_exponent: 0.05,
                upturn_rate: 1.0e3,
            },
            RateTerm::LogThermal {
                rate_sensitivity: 0.014,
                reference_rate: 1.0,
                coupling: 2.0,
                reference_temperature: 298.0,
                melting_temperature: 1793.0,
            },
        ];
        for term in terms {
            let (rate, h) = (5.0e3, 1.0e-2);
            let numeric = (term.evaluate(rate + h, 600.0).value
                - term.evaluate(rate - h, 600.0).value)
                / (2.0 * h);
            let analytic = term.evaluate(rate, 600.0).slope;
            assert!(
                (numeric / analytic - 1.0).abs() < 1e-6,
                "{numeric} vs {analytic}"
            );
        }
    }
}

// Search ranges of the diagnosis' added terms: the upturn exponent in [0, 0.5]; the
// rate-temperature coupling in [-1, 10] (at -1 the sensitivity vanishes at melt).
crate::enum_constants!(RateTerm, {
    None {},
    JohnsonCookLog {
        rate_sensitivity = ("C", "-", parameters::RATE_SENSITIVITY),
        reference_rate = ("e0", "1/s", parameters::FIXED),
    },
    Power {
        exponent = ("beta", "-", parameters::RATE_SENSITIVITY),
        reference_rate = ("e0", "1/s", parameters::FIXED),
    },
    TwoPart {
        exponent_1 = ("beta1", "-", parameters::RATE_SENSITIVITY),
        reference_rate_1 = ("e01", "1/s", Some((1.0e-4, 1.0))),
        exponent_2 = ("beta2", "-", parameters::RATE_SENSITIVITY),
        reference_rate_2 = ("e02", "1/s", Some((1.0, 1.0e4))),
    },
    LogUpturn {
        rate_sensitivity = ("C", "-", parameters::RATE_SENSITIVITY),
        reference_rate = ("e0", "1/s", parameters::FIXED),
        upturn_exponent = ("beta", "-", Some((0.0, 0.5))),
        upturn_rate = ("e_up", "1/s", parameters::FIXED),
    },
    LogThermal {
        rate_sensitivity = ("C", "-", parameters::RATE_SENSITIVITY),
        reference_rate = ("e0", "1/s", parameters::FIXED),
        coupling = ("kappa", "-", Some((-1.0, 10.0))),
        reference_temperature = ("Tr", "K", parameters::FIXED),
        melting_temperature = ("Tm", "K", parameters::FIXED),
    },
    CowperSymonds {
        rate_constant = ("D", "1/s", Some((1.0, 1.0e8))),
        exponent = ("q", "-", Some((1.0, 10.0))),
    },
});
