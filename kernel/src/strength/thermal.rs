//! Thermal-softening terms `theta(T)`.

use crate::error::{check, ParameterError};
use crate::math::lanes::{Calls, Direct, Function, Transcendentals};
use crate::parameters;

/// Homologous temperature `T* = (T - Tr)/(Tm - Tr)` clamped to `[0, 1]`.
#[inline]
pub fn homologous_temperature(
    temperature: f64,
    reference_temperature: f64,
    melting_temperature: f64,
) -> f64 {
    let ratio =
        (temperature - reference_temperature) / (melting_temperature - reference_temperature);
    crate::math::clamp(ratio, 0.0, 1.0)
}

/// Johnson-Cook's `1 - T*^m` (exactly 1 at or below `Tr`, where `pow` is not called).
#[inline]
fn homologous_power(
    temperature: f64,
    exponent: f64,
    reference_temperature: f64,
    melting_temperature: f64,
    math: &mut impl Transcendentals,
) -> f64 {
    let t_star = homologous_temperature(temperature, reference_temperature, melting_temperature);
    if t_star == 0.0 {
        1.0
    } else {
        1.0 - math.pow(t_star, exponent)
    }
}

/// Multiplicative thermal-softening factor on the flow stress.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "kebab-case"))]
pub enum ThermalTerm {
    /// No thermal softening: `theta = 1`.
    None,
    /// Johnson-Cook: `1 - T*^m`.
    HomologousPower {
        /// Exponent `m` (-).
        exponent: f64,
        /// Reference (room) temperature `Tr` (K).
        reference_temperature: f64,
        /// Melting temperature `Tm` (K).
        melting_temperature: f64,
    },
    /// Johnson-Cook with a second softening stage: `(1 - T*^m)(1 - d S(T))`, `S` the smooth
    /// step `x^2 (3 - 2x)` of `x = (T - Ts)/(Te - Ts)` clamped to `[0, 1]`: a strength drop
    /// by the fraction `d` spread from `Ts` to `Te` (a phase change or a tempering stage that
    /// a single power of `T*` cannot follow). At `d = 0` it is `1 - T*^m` bit for bit.
    HomologousPowerDrop {
        /// Exponent `m` (-).
        exponent: f64,
        /// Reference (room) temperature `Tr` (K).
        reference_temperature: f64,
        /// Melting temperature `Tm` (K).
        melting_temperature: f64,
        /// Fraction `d` of the strength lost in the drop (-), `0 <= d < 1`.
        drop: f64,
        /// Temperature `Ts` where the drop starts (K).
        drop_start_temperature: f64,
        /// Temperature `Te` where the drop ends (K), above `Ts`.
        drop_end_temperature: f64,
    },
    /// Linear in homologous temperature: `1 - T*`.
    Linear {
        /// Reference temperature `Tr` (K).
        reference_temperature: f64,
        /// Melting temperature `Tm` (K).
        melting_temperature: f64,
    },
}

impl ThermalTerm {
    /// `theta(T)`.
    #[inline]
    pub fn evaluate(&self, temperature: f64) -> f64 {
        self.evaluate_with(temperature, &mut Direct)
    }

    /// Announce the call [`ThermalTerm::evaluate_with`] makes at `temperature` (see
    /// [`Calls`]): `pow(T*, m)` of the homologous power forms.
    #[inline(always)]
    pub fn announce(&self, temperature: f64, calls: &mut Calls) {
        if let ThermalTerm::HomologousPower {
            exponent,
            reference_temperature,
            melting_temperature,
        }
        | ThermalTerm::HomologousPowerDrop {
            exponent,
            reference_temperature,
            melting_temperature,
            ..
        } = *self
        {
            let t_star =
                homologous_temperature(temperature, reference_temperature, melting_temperature);
            calls.push(
                Function::Pow,
                if t_star == 0.0 { 1.0 } else { t_star },
                exponent,
            );
        }
    }

    /// [`ThermalTerm::evaluate`] with its `pow` from `math`.
    #[inline(always)]
    pub fn evaluate_with(&self, temperature: f64, math: &mut impl Transcendentals) -> f64 {
        match *self {
            ThermalTerm::None => 1.0,
            ThermalTerm::HomologousPower {
                exponent,
                reference_temperature,
                melting_temperature,
            } => homologous_power(
                temperature,
                exponent,
                reference_temperature,
                melting_temperature,
                math,
            ),
            ThermalTerm::HomologousPowerDrop {
                exponent,
                reference_temperature,
                melting_temperature,
                drop,
                drop_start_temperature,
                drop_end_temperature,
            } => {
                let power = homologous_power(
                    temperature,
                    exponent,
                    reference_temperature,
                    melting_temperature,
                    math,
                );
                let x = crate::math::clamp(
                    (temperature - drop_start_temperature)
                        / (drop_end_temperature - drop_start_temperature),
                    0.0,
                    1.0,
                );
                power * (1.0 - drop * (x * x * (3.0 - 2.0 * x)))
            }
            ThermalTerm::Linear {
                reference_temperature,
                melting_temperature,
            } => {
                1.0 - homologous_temperature(
                    temperature,
                    reference_temperature,
                    melting_temperature,
                )
            }
        }
    }

    /// The reference and melting temperatures `(Tr, Tm)` of a homologous term.
    pub fn temperature_limits(&self) -> Option<(f64, f64)> {
        match *self {
            ThermalTerm::None => None,
            ThermalTerm::HomologousPower {
                reference_temperature,
                melting_temperature,
                ..
            }
            | ThermalTerm::HomologousPowerDrop {
                reference_temperature,
                melting_temperature,
                ..
            }
            | ThermalTerm::Linear {
                reference_temperature,
                melting_temperature,
            } => Some((reference_temperature, melting_temperature)),
        }
    }

    /// Temperatures a table of `theta` must sample to follow the drop: nine, evenly from its
    /// start to its end (linear interpolation of the smooth step over an eighth of its span
    /// errs by at most `6 d / (8 * 64)`, 1.2 % of the drop's depth `d`).
    pub fn knots(&self) -> Option<[f64; 9]> {
        match *self {
            ThermalTerm::HomologousPowerDrop {
                drop_start_temperature,
                drop_end_temperature,
                ..
            } => Some(core::array::from_fn(|k| {
                drop_start_temperature
                    + (drop_end_temperature - drop_start_temperature) * k as f64 / 8.0
            })),
            _ => None,
        }
    }

    /// Reject non-physical constants: `m > 0`, `0 < Tr < Tm`; for the drop `0 <= d < 1`,
    /// `0 < Ts < Te`.
    pub fn validate(&self) -> Result<(), ParameterError> {
        let (reference_temperature, melting_temperature) = match *self {
            ThermalTerm::None => return Ok(()),
            ThermalTerm::HomologousPower {
                exponent,
                reference_temperature,
                melting_temperature,
            } => {
                check::range("thermal_exponent", exponent, 1e-3, 10.0)?;
                (reference_temperature, melting_temperature)
            }
            ThermalTerm::HomologousPowerDrop {
                exponent,
                reference_temperature,
                melting_temperature,
                drop,
                drop_start_temperature,
                drop_end_temperature,
            } => {
                check::range("thermal_exponent", exponent, 1e-3, 10.0)?;
                check::range("drop", drop, 0.0, 0.999)?;
                check::positive("drop_start_temperature", drop_start_temperature)?;
                if drop_end_temperature <= drop_start_temperature {
                    return Err(ParameterError::Inconsistent {
                        field: "drop_end_temperature",
                        other: "drop_start_temperature",
                    });
                }
                (reference_temperature, melting_temperature)
            }
            ThermalTerm::Linear {
                reference_temperature,
                melting_temperature,
            } => (reference_temperature, melting_temperature),
        };
        check::positive("reference_temperature", reference_temperature)?;
        check::positive("melting_temperature", melting_temperature)?;
        if melting_temperature <= reference_temperature {
            return Err(ParameterError::Inconsistent {
                field: "melting_temperature",
                other: "reference_temperature",
            });
        }
        Ok(())
    }
}

crate::enum_constants!(ThermalTerm, {
    None {},
    HomologousPower {
        exponent = ("m", "-", parameters::THERMAL_EXPONENT),
        reference_temperature = ("Tr", "K", parameters::FIXED),
        melting_temperature = ("Tm", "K", parameters::FIXED),
    },
    HomologousPowerDrop {
        exponent = ("m", "-", parameters::THERMAL_EXPONENT),
        reference_temperature = ("Tr", "K", parameters::FIXED),
        melting_temperature = ("Tm", "K", parameters::FIXED),
        drop = ("d", "-", parameters::THERMAL_DROP),
        drop_start_temperature = ("Ts", "K", parameters::FIXED),
        drop_end_temperature = ("Te", "K", parameters::FIXED),
    },
    Linear {
        reference_temperature = ("Tr", "K", parameters::FIXED),
        melting_temperature = ("Tm", "K", parameters::FIXED),
    },
});

#[cfg(test)]
mod tests {
    use super::*;

    const POWER: ThermalTerm = ThermalTerm::HomologousPower {
        exponent: 1.05,
        reference_temperature: 298.0,
        melting_temperature: 1793.0,
    };

    fn with_drop(drop: f64) -> ThermalTerm {
        ThermalTerm::HomologousPowerDrop {
            exponent: 1.05,
            reference_temperature: 298.0,
            melting_temperature: 1793.0,
            drop,
            drop_start_temperature: 840.0,
            drop_end_temperature: 960.0,
        }
    }

    #[test]
    fn a_drop_of_zero_is_the_power_law_bit_for_bit() {
        // GOAL: the diagnosis' thermal-drop term is nested: at d = 0 it is 1 - T*^m exactly.
        // SETUP: 2000 temperatures from 200 to 2000 K (below Tr, through the drop, above Tm).
        // REFERENCE: ThermalTerm::HomologousPower's value, compared by bits.
        for k in 0..2000 {
            let t = 200.0 + 0.9 * k as f64;
            assert_eq!(
                with_drop(0.0).evaluate(t).to_bits(),
                POWER.evaluate(t).to_bits(),
                "{t} K"
            );
        }
    }

    #[test]
    fn the_drop_is_a_smooth_step_between_its_temperatures() {
        // GOAL: theta = (1 - T*^m)(1 - d S), S the smooth step x^2 (3 - 2x) over [Ts, Te].
        // SETUP: d = 0.25 over 840-960 K.
        // REFERENCE: the closed form: no drop below Ts, d/2 at the middle, d above Te, and
        //        S'(x) = 6x(1 - x) vanishes at both ends (checked by one-sided differences).
        let term = with_drop(0.25);
        let ratio = |t: f64| term.evaluate(t) / POWER.evaluate(t);
        assert_eq!(ratio(700.0), 1.0);
        assert_eq!(ratio(840.0), 1.0);
        assert!((ratio(900.0) - 0.875).abs() < 1e-14);
        assert!((ratio(960.0) - 0.75).abs() < 1e-14);
        assert!((ratio(1200.0) - 0.75).abs() < 1e-14);
        let x: f64 = 0.3;
        let expected = 1.0 - 0.25 * x * x * (3.0 - 2.0 * x);
        assert!((ratio(840.0 + 120.0 * x) - expected).abs() < 1e-14);
        let h = 1e-3;
        assert!((ratio(840.0 + h) - 1.0).abs() < 1e-6);
        assert!((ratio(960.0 - h) - 0.75).abs() < 1e-6);
    }

    #[test]
    fn a_drop_outside_its_range_or_with_reversed_temperatures_is_refused() {
        // GOAL: validation names the field. SETUP: d = 1, d < 0, Te <= Ts, Ts <= 0.
        // REFERENCE: ParameterError naming `drop`, `drop_end_temperature`,
        //        `drop_start_temperature`.
        assert!(with_drop(0.5).validate().is_ok());
        for bad in [1.0, -0.1, f64::NAN] {
            assert!(with_drop(bad).validate().is_err(), "drop {bad}");
        }
        let mut reversed = with_drop(0.2);
        if let ThermalTerm::HomologousPowerDrop {
            drop_end_temperature,
            ..
        } = &mut reversed
        {
            *drop_end_temperature = 840.0;
        }
        assert_eq!(
            reversed.validate(),
            Err(ParameterError::Inconsistent {
                field: "drop_end_temperature",
                other: "drop_start_temperature",
            })
        );
        let mut cold = with_drop(0.2);
        if let ThermalTerm::HomologousPowerDrop {
            drop_start_temperature,
            ..
        } = &mut cold
        {
            *drop_start_temperature = 0.0;
        }
        assert!(cold.validate().is_err());
    }
}
