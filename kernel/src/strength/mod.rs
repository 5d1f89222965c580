//! Flow-stress (strength) models: `sigma_y(eps_p, deps_p, T)` and its partial derivatives.
//!
//! A model is either a [`ComposedStrength`] — a product of a hardening term, a rate term and a
//! thermal term, each an enum, so that a missing term can be added without writing a new
//! model — or [`ZerilliArmstrong`], [`PrestonTonksWallace`], [`KhanHuangLiang`],
//! [`VoceKocks`] or [`MechanicalThresholdStress`], whose rate dependence is coupled with the
//! temperature or the strain.
//!
//! The named families of seed 000 (JC, ZA, MJC, TJC) are parameter structs with `validate()`
//! and their constants' descriptions ([`crate::parameters`]); each converts into a
//! [`Strength`].

mod composed;
mod hardening;
mod johnson_cook;
mod khan_huang_liang;
mod mechanical_threshold_stress;
mod modified_johnson_cook;
mod preston_tonks_wallace;
mod rate;
mod thermal;
mod two_rate_johnson_cook;
mod voce_kocks;
mod zerilli_armstrong;

pub use composed::ComposedStrength;
pub use hardening::Hardening;
pub use johnson_cook::JohnsonCook;
pub use khan_huang_liang::KhanHuangLiang;
pub use mechanical_threshold_stress::MechanicalThresholdStress;
pub use modified_johnson_cook::ModifiedJohnsonCook;
pub use preston_tonks_wallace::PrestonTonksWallace;
pub use rate::RateTerm;
pub use thermal::{homologous_temperature, ThermalTerm};
pub use two_rate_johnson_cook::TwoRateJohnsonCook;
pub use voce_kocks::VoceKocks;
pub use zerilli_armstrong::{CrystalStructure, ZerilliArmstrong};

use crate::error::ParameterError;
use crate::math::lanes::{Calls, Direct, Transcendentals};

/// A flow stress and its partial derivatives at fixed temperature.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlowStress {
    /// `sigma_y` (Pa).
    pub value: f64,
    /// `d sigma_y / d eps_p` (Pa).
    pub d_plastic_strain: f64,
    /// `d sigma_y / d deps_p` (Pa s).
    pub d_rate: f64,
}

/// A plastic strain rate held at `floor` below it, and whether it was above (where the rate
/// derivatives of a model with a rate floor are its law's; below, they are 0).
#[inline]
pub(crate) fn floored_rate(plastic_strain_rate: f64, floor: f64) -> (f64, bool) {
    if plastic_strain_rate > floor {
        (plastic_strain_rate, true)
    } else {
        (floor, false)
    }
}

impl FlowStress {
    /// This flow stress, taken at a return path's point `(eps_n + dl, dl/dt)`, as a
    /// [`PathFlow`]: the exact first derivative in `dl`, `d sigma/d eps + (d sigma/d rate) /
    /// dt`, and unbounded second and third, for the models that provide no higher derivatives
    /// (Preston-Tonks-Wallace, Khan-Huang-Liang, Voce-Kocks, Mechanical Threshold Stress): the
    /// return mapping then converges by safeguarded Newton steps and evaluates the flow stress
    /// where it stops.
    #[inline]
    pub fn first_order_path(self, inverse_dt: f64, kink_rate: f64) -> PathFlow {
        PathFlow {
            value: self.value,
            slope: self.d_plastic_strain + self.d_rate * inverse_dt,
            curvature: f64::INFINITY,
            third: f64::INFINITY,
            kink_rate,
        }
    }
}

/// The flow stress along a return path, `sigma_y(eps_n + dl, dl/dt)` at fixed temperature,
/// and its first three derivatives in the plastic multiplier `dl`.
///
/// The return mapping's residual is `q_trial - 3G dl - sigma_y`: these derivatives give its
/// Newton step, a third-order correction of that step, and the size of what the corrected step
/// leaves, so that the return can stop without evaluating the flow stress again. They hold on
/// the smooth branch the point is on: the flow stress is not differentiable at `kink_rate`
/// (e.g. Johnson-Cook's `1 + C ln e*` switching to 1 at `e* = 1`), and a step across it proves
/// nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathFlow {
    /// `sigma_y` (Pa).
    pub value: f64,
    /// `d sigma_y / d dl` (Pa): `d sigma_y / d eps_p + (d sigma_y / d deps_p) / dt`.
    pub slope: f64,
    /// `d2 sigma_y / d dl^2` (Pa); `+inf` where unbounded.
    pub curvature: f64,
    /// `d3 sigma_y / d dl^3` (Pa); `+inf` where unbounded.
    pub third: f64,
    /// Plastic strain rate (1/s) at which the flow stress changes branch; 0 if it has none at
    /// positive rates.
    pub kink_rate: f64,
}

impl PathFlow {
    /// `true` if the multipliers `a` and `b` over the step `dt` (rates `a/dt`, `b/dt`) lie on
    /// the same smooth branch (no kink between them).
    #[inline]
    pub fn same_branch(&self, a: f64, b: f64, dt: f64) -> bool {
        let kink = self.kink_rate * dt;
        self.kink_rate <= 0.0 || (a - kink) * (b - kink) > 0.0
    }
}

/// A one-variable factor of a flow stress with its first three derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TermValue {
    /// The factor.
    pub value: f64,
    /// Its first derivative.
    pub slope: f64,
    /// Its second derivative (`+inf` where unbounded).
    pub curvature: f64,
    /// Its third derivative (`+inf` where unbounded).
    pub third: f64,
}

impl TermValue {
    /// The constant 0.
    pub const CONSTANT_ZERO: TermValue = TermValue {
        value: 0.0,
        slope: 0.0,
        curvature: 0.0,
        third: 0.0,
    };

    /// The constant 1.
    pub const CONSTANT_ONE: TermValue = TermValue {
        value: 1.0,
        slope: 0.0,
        curvature: 0.0,
        third: 0.0,
    };

    /// `offset + self`.
    #[inline(always)]
    pub fn plus(self, offset: f64) -> TermValue {
        TermValue {
            value: offset + self.value,
            ..self
        }
    }

    /// `self + other`.
    #[inline(always)]
    pub fn sum(self, other: &TermValue) -> TermValue {
        TermValue {
            value: self.value + other.value,
            slope: self.slope + other.slope,
            curvature: self.curvature + other.curvature,
            third: self.third + other.third,
        }
    }

    /// `self * other` (Leibniz's rule to the third derivative).
    #[inline(always)]
    pub fn product(self, other: &TermValue) -> TermValue {
        TermValue {
            value: self.value * other.value,
            slope: self.slope * other.value + self.value * other.slope,
            curvature: self.curvature * other.value
                + 2.0 * self.slope * other.slope
                + self.value * other.curvature,
            third: self.third * other.value
                + 3.0 * (self.curvature * other.slope + self.slope * other.curvature)
                + self.value * other.third,
        }
    }

    /// `self * factor` (a constant factor).
    #[inline(always)]
    pub fn scaled(self, factor: f64) -> TermValue {
        TermValue {
            value: self.value * factor,
            slope: self.slope * factor,
            curvature: self.curvature * factor,
            third: self.third * factor,
        }
    }

    /// A factor of the rate `deps_p = dl/dt` seen as a function of `dl`: its derivatives
    /// times `1/dt`, `1/dt^2`, `1/dt^3`.
    #[inline(always)]
    pub fn along_rate(self, inverse_dt: f64) -> TermValue {
        TermValue {
            value: self.value,
            slope: self.slope * inverse_dt,
            curvature: self.curvature * inverse_dt * inverse_dt,
            third: self.third * inverse_dt * inverse_dt * inverse_dt,
        }
    }

    /// This factor as a [`PathFlow`] with the given kink rate.
    #[inline(always)]
    pub fn path_flow(self, kink_rate: f64) -> PathFlow {
        PathFlow {
            value: self.value,
            slope: self.slope,
            curvature: self.curvature,
            third: self.third,
            kink_rate,
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
    /// Preston-Tonks-Wallace: glide and overdriven shock regimes, scaled by the shear modulus.
    PrestonTonksWallace(PrestonTonksWallace),
    /// Khan-Huang-Liang: strain hardening coupled with the rate.
    KhanHuangLiang(KhanHuangLiang),
    /// Voce-Kocks: Voce hardening to a rate- and temperature-dependent saturation.
    VoceKocks(VoceKocks),
    /// Mechanical Threshold Stress (Follansbee-Kocks): thermally activated parts of a
    /// threshold stress that evolves with strain, scaled by the shear modulus.
    MechanicalThresholdStress(MechanicalThresholdStress),
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

    /// The model at a fixed temperature, with its temperature-only factor evaluated once: the
    /// return mapping holds `T_n` fixed while it iterates on the plastic multiplier.
    #[inline]
    pub fn at_temperature(&self, temperature: f64) -> FlowAtTemperature<'_> {
        self.at_temperature_with(temperature, &mut Direct)
    }

    /// Whether this model announces its transcendental calls ([`Self::announce_temperature`],
    /// [`Self::announce_path`]) so that a group can evaluate them in lanes: the composed models
    /// and Zerilli-Armstrong.
    #[inline(always)]
    pub fn announces_calls(&self) -> bool {
        matches!(self, Strength::Composed(_) | Strength::ZerilliArmstrong(_))
    }

    /// Announce the calls [`Strength::at_temperature_with`] makes (see [`Calls`]; a composed
    /// model's thermal factor).
    #[inline(always)]
    pub fn announce_temperature(&self, temperature: f64, calls: &mut Calls) {
        if let Strength::Composed(model) = self {
            model.thermal.announce(temperature, calls);
        }
    }

    /// Announce the calls [`FlowAtTemperature::along_path_with`] makes for this model at
    /// `temperature` (see [`Calls`]; a composed model's terms, Zerilli-Armstrong's activation
    /// and strain term).
    #[inline(always)]
    pub fn announce_path(
        &self,
        plastic_strain: f64,
        dl: f64,
        inverse_dt: f64,
        temperature: f64,
        calls: &mut Calls,
    ) {
        match self {
            Strength::Composed(model) => model.announce_path(plastic_strain, dl, inverse_dt, calls),
            Strength::ZerilliArmstrong(model) => {
                model.announce_path(plastic_strain, dl, inverse_dt, temperature, calls)
            }
            _ => {}
        }
    }

    /// [`Strength::at_temperature`] with a composed model's transcendental functions from
    /// `math`.
    #[inline(always)]
    pub fn at_temperature_with(
        &self,
        temperature: f64,
        math: &mut impl Transcendentals,
    ) -> FlowAtTemperature<'_> {
        let factor = match self {
            Strength::Composed(model) => model.thermal.evaluate_with(temperature, math),
            Strength::KhanHuangLiang(model) => model.thermal_factor(temperature),
            Strength::PrestonTonksWallace(model) => model.rate_scale(temperature),
            Strength::MechanicalThresholdStress(model) => model.modulus_ratio(temperature),
            Strength::ZerilliArmstrong(_) | Strength::VoceKocks(_) => 1.0,
        };
        FlowAtTemperature {
            strength: self,
            temperature,
            factor,
        }
    }

    /// Reject non-physical parameters.
    pub fn validate(&self) -> Result<(), ParameterError> {
        match self {
            Strength::Composed(model) => model.validate(),
            Strength::ZerilliArmstrong(model) => model.validate(),
            Strength::PrestonTonksWallace(model) => model.validate(),
            Strength::KhanHuangLiang(model) => model.validate(),
            Strength::VoceKocks(model) => model.validate(),
            Strength::MechanicalThresholdStress(model) => model.validate(),
        }
    }
}

/// A [`Strength`] at a fixed temperature (see [`Strength::at_temperature`]). Bit-identical to
/// [`Strength::flow_stress`] at that temperature.
#[derive(Clone, Copy, Debug)]
pub struct FlowAtTemperature<'a> {
    strength: &'a Strength,
    temperature: f64,
    /// The model's temperature-only factor: `theta(T)` of a composed model, `1 - T*^m` of
    /// Khan-Huang-Liang, the rate scale `gamma xi'(T)` of Preston-Tonks-Wallace, `mu(T)/mu_0`
    /// of the Mechanical Threshold Stress; 1 (unused)
    /// for Zerilli-Armstrong and Voce-Kocks, whose temperature acts through the rate.
    factor: f64,
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
                self.factor,
            ),
            Strength::ZerilliArmstrong(model) => {
                model.flow_stress(plastic_strain, plastic_strain_rate, self.temperature)
            }
            Strength::PrestonTonksWallace(model) => model.flow_stress_at_rate_scale(
                plastic_strain,
                plastic_strain_rate,
                self.temperature,
                self.factor,
            ),
            Strength::KhanHuangLiang(model) => {
                model.flow_stress_with_thermal(plastic_strain, plastic_strain_rate, self.factor)
            }
            Strength::VoceKocks(model) => {
                model.flow_stress(plastic_strain, plastic_strain_rate, self.temperature)
            }
            Strength::MechanicalThresholdStress(model) => model.flow_stress_at_modulus_ratio(
                plastic_strain,
                plastic_strain_rate,
                self.temperature,
                self.factor,
            ),
        }
    }
}

impl FlowAtTemperature<'_> {
    /// The flow stress along the return path from plastic strain `plastic_strain` at the
    /// multiplier `dl` over a step of `1/inverse_dt`: `sigma_y(eps_n + dl, dl/dt)` and its
    /// derivatives in `dl`. The rate is `dl * inverse_dt`: the return's reciprocal of the step
    /// is computed once.
    #[inline]
    pub fn along_path(&self, plastic_strain: f64, dl: f64, inverse_dt: f64) -> PathFlow {
        self.along_path_with(plastic_strain, dl, inverse_dt, &mut Direct)
    }

    /// [`Self::along_path`] with a composed model's and Zerilli-Armstrong's transcendental
    /// functions from `math`.
    #[inline(always)]
    pub fn along_path_with(
        &self,
        plastic_strain: f64,
        dl: f64,
        inverse_dt: f64,
        math: &mut impl Transcendentals,
    ) -> PathFlow {
        match self.strength {
            Strength::Composed(model) => model.along_path_with(
                plastic_strain,
                dl,
                inverse_dt,
                self.temperature,
                self.factor,
                math,
            ),
            Strength::ZerilliArmstrong(model) => {
                model.along_path_with(plastic_strain, dl, inverse_dt, self.temperature, math)
            }
            Strength::PrestonTonksWallace(_) => self
                .flow_stress(plastic_strain + dl, dl * inverse_dt)
                .first_order_path(inverse_dt, PrestonTonksWallace::MINIMUM_RATE),
            Strength::KhanHuangLiang(_) => self
                .flow_stress(plastic_strain + dl, dl * inverse_dt)
                .first_order_path(inverse_dt, KhanHuangLiang::MINIMUM_RATE),
            Strength::VoceKocks(_) => self
                .flow_stress(plastic_strain + dl, dl * inverse_dt)
                .first_order_path(inverse_dt, VoceKocks::MINIMUM_RATE),
            Strength::MechanicalThresholdStress(_) => self
                .flow_stress(plastic_strain + dl, dl * inverse_dt)
                .first_order_path(inverse_dt, MechanicalThresholdStress::MINIMUM_RATE),
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

impl From<PrestonTonksWallace> for Strength {
    fn from(model: PrestonTonksWallace) -> Self {
        Strength::PrestonTonksWallace(model)
    }
}

impl From<KhanHuangLiang> for Strength {
    fn from(model: KhanHuangLiang) -> Self {
        Strength::KhanHuangLiang(model)
    }
}

impl From<VoceKocks> for Strength {
    fn from(model: VoceKocks) -> Self {
        Strength::VoceKocks(model)
    }
}

impl From<MechanicalThresholdStress> for Strength {
    fn from(model: MechanicalThresholdStress) -> Self {
        Strength::MechanicalThresholdStress(model)
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
    fn path_derivatives_match_central_differences() {
        // GOAL: the derivatives along a return path that the return's stopping test and its
        //       corrected step rely on are those of sigma_y(eps_n + dl, dl/dt).
        // SETUP: every form of `models()`, eps_n 0.05 and 0.4, dl giving rates 50 and 2e4 /s
        //        over dt 1e-6 s, 600 K.
        // REFERENCE: central differences in dl (step 1e-4 of dl) of the value, the slope and
        //            the curvature; agreement to 1e-5 of the derivative or of the next lower
        //            one times 1/dl, whichever is larger. The value and slope are those of
        //            `flow_stress` to round-off.
        let dt = 1.0e-6;
        for model in models() {
            let at = model.at_temperature(600.0);
            for strain in [0.05, 0.4] {
                for rate in [50.0, 2.0e4] {
                    let dl = rate * dt;
                    let f = at.along_path(strain, dl, 1.0 / dt);
                    let h = 1.0e-4 * dl;
                    let (p, m) = (
                        at.along_path(strain, dl + h, 1.0 / dt),
                        at.along_path(strain, dl - h, 1.0 / dt),
                    );
                    let close = |numeric: f64, analytic: f64, lower: f64| {
                        (numeric - analytic).abs() <= 1.0e-5 * analytic.abs().max(lower.abs() / dl)
                    };
                    let slope = (p.value - m.value) / (2.0 * h);
                    let curvature = (p.slope - m.slope) / (2.0 * h);
                    let third = (p.curvature - m.curvature) / (2.0 * h);
                    assert!(
                        close(slope, f.slope, f.value),
                        "{model:?}: {slope} vs {}",
                        f.slope
                    );
                    assert!(
                        close(curvature, f.curvature, f.slope),
                        "{model:?}: {curvature} vs {}",
                        f.curvature
                    );
                    assert!(
                        close(third, f.third, f.curvature),
                        "{model:?}: {third} vs {}",
                        f.third
                    );
                    let partials = at.flow_stress(strain + dl, rate);
                    let path_slope = partials.d_plastic_strain + partials.d_rate / dt;
                    assert!((partials.value - f.value).abs() <= 1.0e-15 * f.value);
                    assert!((path_slope - f.slope).abs() <= 1.0e-12 * f.slope.abs());
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
        let along = |model: &Strength| model.at_temperature(300.0).along_path(0.1, 1.0e-5, 1.0e6);
        let jc = along(&jc);
        assert_eq!(jc.kink_rate, 1.0);
        assert!(jc.same_branch(10.0, 2.0, 1.0) && !jc.same_branch(10.0, 0.5, 1.0));
        assert_eq!(along(&za).kink_rate, 1.0e-6);
        assert!(along(&mjc).same_branch(10.0, 1.0e-9, 1.0));
    }
}

/// The families' constants read and written by name, index and composed path
/// ([`crate::parameters`]).
#[cfg(test)]
mod described_tests {
    use super::{ComposedStrength, JohnsonCook, ModifiedJohnsonCook, RateTerm, TwoRateJohnsonCook};
    use crate::parameters::{ConstantPaths, Constants};

    /// Distinct values in every slot of `model`, written by index.
    fn numbered<M: Constants>(mut model: M) -> M {
        for index in 0..model.parameters().len() {
            *model.slot(index).unwrap() = 1000.0 + index as f64;
        }
        assert!(model.slot(model.parameters().len()).is_none());
        model
    }

    fn check_paths(model: ComposedStrength, values: &[f64], paths: &[&str]) {
        assert_eq!(values.len(), paths.len());
        for (value, path) in values.iter().zip(paths) {
            assert_eq!(model.get(path), Some(*value), "{path}");
        }
        assert_eq!(model.parameters().count(), paths.len());
    }

    #[test]
    fn the_families_composed_paths_find_each_constant_where_composed_puts_it() {
        // GOAL: a family constant keeps its value when the family is rewritten as composed
        //       terms (the diagnosis adds physics terms to that form).
        // SETUP: JC, MJC, TJC with a distinct number in every constant, by index.
        // REFERENCE: `composed()` holds constant i at COMPOSED_PATHS[i], and the composed
        //            form has no other constant.
        let jc = numbered(JohnsonCook::STEEL_4340);
        let values: std::vec::Vec<f64> = (0..8).map(|i| 1000.0 + i as f64).collect();
        check_paths(jc.composed(), &values, &JohnsonCook::COMPOSED_PATHS);
        let mjc = numbered(ModifiedJohnsonCook {
            yield_stress: 0.0,
            hardening_modulus: 0.0,
            hardening_exponent: 0.0,
            saturation_stress_1: 0.0,
            saturation_rate_1: 0.0,
            saturation_stress_2: 0.0,
            saturation_rate_2: 0.0,
            rate_exponent: 0.0,
            reference_rate: 0.0,
            thermal_exponent: 0.0,
            reference_temperature: 0.0,
            melting_temperature: 0.0,
        });
        let values: std::vec::Vec<f64> = (0..12).map(|i| 1000.0 + i as f64).collect();
        check_paths(
            mjc.composed(),
            &values,
            &ModifiedJohnsonCook::COMPOSED_PATHS,
        );
        let tjc = numbered(TwoRateJohnsonCook {
            yield_stress: 0.0,
            hardening_modulus: 0.0,
            hardening_exponent: 0.0,
            saturation_stress_1: 0.0,
            saturation_rate_1: 0.0,
            saturation_stress_2: 0.0,
            saturation_rate_2: 0.0,
            rate_exponent_1: 0.0,
            reference_rate_1: 0.0,
            rate_exponent_2: 0.0,
            reference_rate_2: 0.0,
            thermal_exponent: 0.0,
            reference_temperature: 0.0,
            melting_temperature: 0.0,
        });
        let values: std::vec::Vec<f64> = (0..14).map(|i| 1000.0 + i as f64).collect();
        check_paths(tjc.composed(), &values, &TwoRateJohnsonCook::COMPOSED_PATHS);
    }

    #[test]
    fn constants_are_read_and_written_by_name_and_path() {
        // GOAL: named access reads and writes the field of that name, nothing else.
        // SETUP: JC 4340 and its composed form with a high-rate upturn.
        // REFERENCE: the struct fields themselves.
        let mut jc = JohnsonCook::STEEL_4340;
        assert_eq!(jc.get("rate_sensitivity"), Some(0.014));
        jc.set("rate_sensitivity", 0.02).unwrap();
        assert_eq!(jc.rate_sensitivity, 0.02);
        assert_eq!(jc.yield_stress, JohnsonCook::STEEL_4340.yield_stress);
        assert!(jc.set("upturn_exponent", 0.1).is_none());
        let mut composed = JohnsonCook::STEEL_4340.composed();
        composed.rate = RateTerm::LogUpturn {
            rate_sensitivity: 0.014,
            reference_rate: 1.0,
            upturn_exponent: 0.0,
            upturn_rate: 1.0e3,
        };
        composed.set("rate.upturn_exponent", 0.2).unwrap();
        assert_eq!(composed.get("rate.upturn_exponent"), Some(0.2));
        assert_eq!(composed.get("hardening.exponent"), Some(0.26));
        assert!(composed.set("rate.coupling", 1.0).is_none());
        assert!(composed.get("thermal").is_none());
        let symbols: std::vec::Vec<&str> = composed.parameters().map(|(_, p)| p.symbol).collect();
        assert_eq!(
            symbols,
            ["A", "B", "n", "C", "e0", "beta", "e_up", "m", "Tr", "Tm"]
        );
    }
}
