//! Flow-stress (strength) models: `sigma_y(eps_p, deps_p, T)` and its partial derivatives.
//!
//! A model is either a [`ComposedStrength`] — a product of a hardening term, a rate term and a
//! thermal term, each an enum, so that a missing term can be added without writing a new
//! model — or [`ZerilliArmstrong`], whose rate and temperature dependence are coupled.
//!
//! The named families of seed 000 (JC, ZA, MJC, TJC) are parameter structs with `validate()`
//! and their constants' descriptions ([`crate::parameters`]); each converts into a
//! [`Strength`].

mod composed;
mod hardening;
mod johnson_cook;
mod modified_johnson_cook;
mod rate;
mod thermal;
mod two_rate_johnson_cook;
mod zerilli_armstrong;

pub use composed::ComposedStrength;
pub use hardening::Hardening;
pub use johnson_cook::JohnsonCook;
pub use modified_johnson_cook::ModifiedJohnsonCook;
pub use rate::RateTerm;
pub use thermal::{homologous_temperature, ThermalTerm};
pub use two_rate_johnson_cook::TwoRateJohnsonCook;
pub use zerilli_armstrong::{CrystalStructure, ZerilliArmstrong};

use crate::error::ParameterError;

/// A flow stress and its first and second partial derivatives at fixed temperature.
///
/// The second derivatives bound how far a Newton step of the return mapping can be from the
/// root (the residual after a step `s` is `g'' s^2 / 2` to leading order), so the return can
/// stop without evaluating the flow stress again. They hold on the smooth branch the point is
/// on: the flow stress is not twice differentiable at `kink_rate` (e.g. Johnson-Cook's
/// `1 + C ln e*` switching to 1 at `e* = 1`), and a step across it proves nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlowStress {
    /// `sigma_y` (Pa).
    pub value: f64,
    /// `d sigma_y / d eps_p` (Pa).
    pub d_plastic_strain: f64,
    /// `d sigma_y / d deps_p` (Pa s).
    pub d_rate: f64,
    /// `d2 sigma_y / d eps_p^2` (Pa); `+inf` where unbounded.
    pub d2_plastic_strain: f64,
    /// `d2 sigma_y / d deps_p^2` (Pa s^2); `+inf` where unbounded.
    pub d2_rate: f64,
    /// `d2 sigma_y / d eps_p d deps_p` (Pa s).
    pub d2_plastic_strain_rate: f64,
    /// Plastic strain rate (1/s) at which the flow stress changes branch (its first or
    /// second rate derivative jumps); 0 if it has none at positive rates.
    pub kink_rate: f64,
}

impl FlowStress {
    /// `|d2 sigma_y / d dl^2|` along a return path `eps_p = eps_n + dl`, `deps_p = dl/dt`:
    /// `sigma_ee + 2 sigma_er / dt + sigma_rr / dt^2` in magnitude.
    #[inline]
    pub fn path_curvature(&self, dt: f64) -> f64 {
        let inverse_dt = 1.0 / dt;
        (self.d2_plastic_strain
            + inverse_dt * (2.0 * self.d2_plastic_strain_rate + inverse_dt * self.d2_rate))
            .abs()
    }

    /// `true` if the rates `a` and `b` lie on the same smooth branch (no kink between them).
    #[inline]
    pub fn same_branch(&self, a: f64, b: f64) -> bool {
        self.kink_rate <= 0.0 || (a - self.kink_rate) * (b - self.kink_rate) > 0.0
    }
}

/// A one-variable factor of a composed flow stress with its first and second derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TermValue {
    /// The factor.
    pub value: f64,
    /// Its first derivative.
    pub slope: f64,
    /// Its second derivative (`+inf` where unbounded).
    pub curvature: f64,
}

impl TermValue {
    /// The constant 0.
    pub const CONSTANT_ZERO: TermValue = TermValue {
        value: 0.0,
        slope: 0.0,
        curvature: 0.0,
    };

    /// The constant 1.
    pub const CONSTANT_ONE: TermValue = TermValue {
        value: 1.0,
        slope: 0.0,
        curvature: 0.0,
    };

    /// `offset + self`.
    #[inline]
    pub fn plus(self, offset: f64) -> TermValue {
        TermValue {
            value: offset + self.value,
            ..self
        }
    }

    /// `self + other`.
    #[inline]
    pub fn sum(self, other: &TermValue) -> TermValue {
        TermValue {
            value: self.value + other.value,
            slope: self.slope + other.slope,
            curvature: self.curvature + other.curvature,
        }
    }

    /// `self * other` (product rule, first and second derivatives).
    #[inline]
    pub fn product(self, other: &TermValue) -> TermValue {
        TermValue {
            value: self.value * other.value,
            slope: self.slope * other.value + self.value * other.slope,
            curvature: self.curvature * other.value
                + 2.0 * self.slope * other.slope
                + self.value * other.curvature,
        }
    }
}

/// A strength model: the von Mises flow stress as a function of equivalent plastic strain,
/// plastic strain rate and temperature.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "kebab-case"))]
pub enum Strength {
    /// `hardening(eps_p) * rate(deps_p) * thermal(T)`.
    Composed(ComposedStrength),
    /// Zerilli-Armstrong (BCC or FCC): rate and temperature coupled.
    ZerilliArmstrong(ZerilliArmstrong),
}

impl Strength {
    /// Flow stress and its derivatives at plastic strain `plastic_strain`, plastic strain rate
    /// `plastic_strain_rate` (1/s) and temperature `temperature` (K).
    #[inline]
    pub fn flow_stress(
        &self,
        plastic_strain: f64,
        plastic_strain_rate: f64,
        temperature: f64,
    ) -> FlowStress {
        self.at_temperature(temperature)
            .flow_stress(plastic_strain, plastic_strain_rate)
    }

    /// The model at a fixed temperature, with its temperature-only factors (the thermal term
    /// `theta(T)` of a composed model) evaluated once: the return mapping holds `T_n` fixed
    /// while it iterates on the plastic multiplier.
    #[inline]
    pub fn at_temperature(&self, temperature: f64) -> FlowAtTemperature<'_> {
        let thermal = match self {
            Strength::Composed(model) => model.thermal.evaluate(temperature),
            Strength::ZerilliArmstrong(_) => 1.0,
        };
        FlowAtTemperature {
            strength: self,
            temperature,
            thermal,
        }
    }

    /// Reject non-physical parameters.
    pub fn validate(&self) -> Result<(), ParameterError> {
        match self {
            Strength::Composed(model) => model.validate(),
            Strength::ZerilliArmstrong(model) => model.validate(),
        }
    }
}

/// A [`Strength`] at a fixed temperature (see [`Strength::at_temperature`]). Bit-identical to
/// [`Strength::flow_stress`] at that temperature.
#[derive(Clone, Copy, Debug)]
pub struct FlowAtTemperature<'a> {
    strength: &'a Strength,
    temperature: f64,
    /// `theta(T)` of a composed model (1 for Zerilli-Armstrong, whose temperature dependence
    /// is coupled with the rate).
    thermal: f64,
}

impl FlowAtTemperature<'_> {
    /// Flow stress and its derivatives at plastic strain `plastic_strain` and plastic strain
    /// rate `plastic_strain_rate` (1/s).
    #[inline]
    pub fn flow_stress(&self, plastic_strain: f64, plastic_strain_rate: f64) -> FlowStress {
        match self.strength {
            Strength::Composed(model) => model.flow_stress_with_thermal(
                plastic_strain,
                plastic_strain_rate,
                self.temperature,
                self.thermal,
            ),
            Strength::ZerilliArmstrong(model) => {
                model.flow_stress(plastic_strain, plastic_strain_rate, self.temperature)
            }
        }
    }
}

impl From<ComposedStrength> for Strength {
    fn from(model: ComposedStrength) -> Self {
        Strength::Composed(model)
    }
}

impl From<ZerilliArmstrong> for Strength {
    fn from(model: ZerilliArmstrong) -> Self {
        Strength::ZerilliArmstrong(model)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every flow-stress form the return mapping meets: JC, MJC (power + Voce, power-law rate),
    /// TJC (two-part rate), the diagnosis's upturn and Cowper-Symonds rates, ZA BCC and FCC.
    fn models() -> [Strength; 7] {
        let hardening = Hardening::PowerVoce2 {
            yield_stress: 792.0e6,
            hardening_modulus: 510.0e6,
            exponent: 0.26,
            saturation_stress_1: 100.0e6,
            saturation_rate_1: 10.0,
            saturation_stress_2: 50.0e6,
            saturation_rate_2: 100.0,
        };
        let thermal = ThermalTerm::HomologousPower {
            exponent: 1.03,
            reference_temperature: 298.0,
            melting_temperature: 1793.0,
        };
        let composed = |rate| {
            Strength::Composed(ComposedStrength {
                hardening,
                rate,
                thermal,
            })
        };
        let za = |structure| {
            Strength::ZerilliArmstrong(ZerilliArmstrong {
                structure,
                athermal_stress: 65.0e6,
                c1: 1033.0e6,
                c2: 900.0e6,
                c3: 0.00698,
                c4: 0.000415,
                c5: 266.0e6,
                exponent: 0.289,
                reference_rate: 1.0,
            })
        };
        [
            Strength::from(JohnsonCook::STEEL_4340),
            composed(RateTerm::Power {
                exponent: 0.01,
                reference_rate: 1.0,
            }),
            composed(RateTerm::TwoPart {
                exponent_1: 0.005,
                reference_rate_1: 1.0e-3,
                exponent_2: 0.05,
                reference_rate_2: 1.0e3,
            }),
            composed(RateTerm::LogUpturn {
                rate_sensitivity: 0.014,
                reference_rate: 1.0,
                upturn_exponent: 0.05,
                upturn_rate: 1.0e3,
            }),
            composed(RateTerm::CowperSymonds {
                rate_constant: 40.0,
                exponent: 5.0,
            }),
            za(CrystalStructure::Bcc),
            za(CrystalStructure::Fcc),
        ]
    }

    #[test]
    fn second_derivatives_match_central_differences_of_the_first() {
        // GOAL: the curvatures the return's stopping test relies on are the flow stress's
        //       second partial derivatives.
        // SETUP: every form of `models()`, at eps_p 0.05 and 0.4, rates 50 and 2e4 /s, 600 K.
        // REFERENCE: central differences of the analytic first derivatives, step 1e-5
        //            relative; agreement to 1e-5 relative (of the largest term for the mixed
        //            derivative, which is zero for ZA BCC).
        for model in models() {
            let at = model.at_temperature(600.0);
            for strain in [0.05, 0.4] {
                for rate in [50.0, 2.0e4] {
                    let f = at.flow_stress(strain, rate);
                    let (he, hr) = (1.0e-5 * strain, 1.0e-5 * rate);
                    let (ep, em) = (
                        at.flow_stress(strain + he, rate),
                        at.flow_stress(strain - he, rate),
                    );
                    let (rp, rm) = (
                        at.flow_stress(strain, rate + hr),
                        at.flow_stress(strain, rate - hr),
                    );
                    let d2e = (ep.d_plastic_strain - em.d_plastic_strain) / (2.0 * he);
                    let d2r = (rp.d_rate - rm.d_rate) / (2.0 * hr);
                    let mixed = (ep.d_rate - em.d_rate) / (2.0 * he);
                    let close = |numeric: f64, analytic: f64, scale: f64| {
                        (numeric - analytic).abs() <= 1.0e-5 * scale.max(analytic.abs())
                    };
                    assert!(
                        close(d2e, f.d2_plastic_strain, 0.0),
                        "{model:?}: {d2e} vs {}",
                        f.d2_plastic_strain
                    );
                    assert!(
                        close(d2r, f.d2_rate, 0.0),
                        "{model:?}: {d2r} vs {}",
                        f.d2_rate
                    );
                    let scale = (f.d_plastic_strain * f.d_rate / f.value).abs();
                    assert!(
                        close(mixed, f.d2_plastic_strain_rate, scale),
                        "{model:?}: {mixed} vs {}",
                        f.d2_plastic_strain_rate
                    );
                }
            }
        }
    }

    #[test]
    fn kinks_are_reported_where_the_rate_factor_switches_branch() {
        // GOAL: a return step across JC's e* = 1 (or ZA's rate floor) is never accepted on
        //       the strength of a curvature taken on the other branch.
        // SETUP: JC 4340 (e0 1 /s); ZA BCC (floor 1e-6 e0); MJC's power-law rate (smooth).
        // REFERENCE: kink rates e0, 1e-6 e0 and none.
        let [jc, mjc, _, _, _, za, _] = models();
        let jc = jc.flow_stress(0.1, 10.0, 300.0);
        assert_eq!(jc.kink_rate, 1.0);
        assert!(jc.same_branch(10.0, 2.0) && !jc.same_branch(10.0, 0.5));
        assert_eq!(za.flow_stress(0.1, 10.0, 300.0).kink_rate, 1.0e-6);
        let mjc = mjc.flow_stress(0.1, 10.0, 300.0);
        assert!(mjc.same_branch(10.0, 1.0e-9));
    }
}
