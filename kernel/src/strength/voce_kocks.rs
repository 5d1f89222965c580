//! Voce-Kocks model: Voce's saturating hardening (Stage III of Kocks & Mecking, Prog. Mater. Sci.
//! 48 (2003) 171, a hardening rate falling linearly with the stress) towards a saturation stress
//! that depends on rate and temperature as Kocks (1976) found (J. Eng. Mater. Technol. 98, 76;
//! Follansbee & Kocks, Acta Metall. 36 (1988) 81, eq. 8):
//!
//! - `sigma_s(deps_p, T) = sigma_s0 (deps_p / e_s0)^(T / T_A)`, with `T_A = mu b^3 A / k` the
//!   activation temperature of the saturation (`mu` shear modulus, `b` Burgers vector, `A` the
//!   normalised activation energy of dynamic recovery, `k` Boltzmann's constant), `e_s0` of
//!   order 1e7 /s;
//! - `sigma_y = sigma_s - (sigma_s - sigma_0) exp(-theta_0 eps_p / sigma_s)`, the integral of
//!   `d sigma / d eps_p = theta_0 (1 - sigma / sigma_s)` from the yield stress `sigma_0` at
//!   constant `sigma_s` (the usual closed form of a Voce law; the rate and temperature histories
//!   of a real path are not integrated, a named simplification shared with every closed-form
//!   family of the kernel).
//!
//! The yield stress `sigma_0` is athermal here: rate and temperature act on the hardening only,
//! through its saturation, which is the Kocks picture of an FCC metal. Below
//! [`VoceKocks::MINIMUM_RATE`] the rate is held at that floor, and the saturation is held at or
//! above [`VoceKocks::SATURATION_FLOOR`] of the yield stress. The value is computed as
//! `sigma_0 - (sigma_s - sigma_0) expm1(-k)` so that no digits cancel at small strain. Along a
//! return path the first derivative is exact and the higher ones are reported unbounded, as for
//! Preston-Tonks-Wallace.

use super::FlowStress;
use crate::error::{check, ParameterError};
use crate::math::{exp, expm1, pow};
use crate::parameters;

/// Voce-Kocks constants (SI).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct VoceKocks {
    /// Yield stress `sigma_0` (Pa).
    pub yield_stress: f64,
    /// Initial hardening rate `theta_0` (Pa).
    pub initial_hardening: f64,
    /// Saturation stress at the reference rate `sigma_s0` (Pa).
    pub saturation_stress: f64,
    /// Reference rate of the saturation `e_s0` (1/s).
    pub saturation_reference_rate: f64,
    /// Activation temperature of the saturation `T_A = mu b^3 A / k` (K).
    pub activation_temperature: f64,
}

impl VoceKocks {
    /// Floor of the plastic strain rate (1/s): below it the flow stress is that at the floor.
    pub const MINIMUM_RATE: f64 = 1e-6;

    /// Floor of the saturation stress as a fraction of the yield stress (hot and slow enough,
    /// Kocks' saturation falls towards 0; a metal that softens to a millionth of its yield
    /// stress has no strength left, and the floor keeps the slopes finite).
    pub const SATURATION_FLOOR: f64 = 1e-6;

    /// Illustrative constants of an annealed FCC metal (copper-like: `sigma_0` 50 MPa,
    /// `theta_0` 2.4 GPa, `sigma_s0` 800 MPa at `e_s0` 1e7 /s, `T_A` 6000 K); not a published
    /// set: the C ABI's base and the checks' sample.
    pub const ILLUSTRATIVE: VoceKocks = VoceKocks {
        yield_stress: 50.0e6,
        initial_hardening: 2.4e9,
        saturation_stress: 800.0e6,
        saturation_reference_rate: 1.0e7,
        activation_temperature: 6000.0,
    };

    /// The saturation stress and its rate derivative at `rate` (floored) and `temperature`.
    #[inline]
    fn saturation(&self, plastic_strain_rate: f64, temperature: f64) -> (f64, f64) {
        let (rate, active) = super::floored_rate(plastic_strain_rate, Self::MINIMUM_RATE);
        let temperature = if temperature > 0.0 { temperature } else { 0.0 };
        let exponent = temperature / self.activation_temperature;
        let value = self.saturation_stress * pow(rate / self.saturation_reference_rate, exponent);
        let slope = if active { value * exponent / rate } else { 0.0 };
        (value, slope)
    }

    /// Flow stress and its strain and rate derivatives at fixed temperature.
    #[inline]
    pub fn flow_stress(
        &self,
        plastic_strain: f64,
        plastic_strain_rate: f64,
        temperature: f64,
    ) -> FlowStress {
        let eps = if plastic_strain > 0.0 {
            plastic_strain
        } else {
            0.0
        };
        let (raw, raw_slope) = self.saturation(plastic_strain_rate, temperature);
        // The saturation is held at or above SATURATION_FLOOR of the yield stress: below it the
        // law's hardening slope theta_0 (1 - sigma_0/sigma_s) is unbounded at the yield.
        // (At least the smallest normal double: a subnormal yield stress would otherwise floor
        // the saturation at zero, and `k` below at 0/0.)
        let floor = (Self::SATURATION_FLOOR * self.yield_stress).max(f64::MIN_POSITIVE);
        let (saturation, d_saturation) = if raw > floor {
            (raw, raw_slope)
        } else {
            (floor, 0.0)
        };
        let span = saturation - self.yield_stress;
        let k = self.initial_hardening * eps / saturation;
        let e = exp(-k);
        // d sigma / d sigma_s = 1 - e^-k (1 + k (sigma_s - sigma_0) / sigma_s), whose limit is 1
        // where e^-k underflows (k e^-k -> 0; k itself may have overflowed, and 0 * inf is not
        // a number).
        let d_value_d_saturation = if e > 0.0 {
            1.0 - e * (1.0 + k * span / saturation)
        } else {
            1.0
        };
        FlowStress {
            value: self.yield_stress - span * expm1(-k),
            d_plastic_strain: self.initial_hardening * span / saturation * e,
            d_rate: d_value_d_saturation * d_saturation,
        }
    }

    /// Reject non-physical constants: positive stresses, non-negative hardening, positive
    /// reference rate and activation temperature.
    pub fn validate(&self) -> Result<(), ParameterError> {
        check::positive("yield_stress", self.yield_stress)?;
        check::non_negative("initial_hardening", self.initial_hardening)?;
        check::positive("saturation_stress", self.saturation_stress)?;
        check::positive("saturation_reference_rate", self.saturation_reference_rate)?;
        check::positive("activation_temperature", self.activation_temperature)?;
        Ok(())
    }
}

// Search ranges: stresses as every stress; theta_0 up to 20 GPa (of order G/20 for FCC
// metals); T_A from 1000 to 50000 K (mu b^3 A / k for A of 0.05-1 and the metals' mu b^3); the
// reference rate is fixed (Follansbee & Kocks: 1e7 /s).
crate::struct_constants!(
    VoceKocks,
    [
        yield_stress = ("sigma_0", "Pa", parameters::STRESS),
        initial_hardening = ("theta_0", "Pa", Some((0.0, 20.0e9))),
        saturation_stress = ("sigma_s0", "Pa", parameters::STRESS),
        saturation_reference_rate = ("e_s0", "1/s", parameters::FIXED),
        activation_temperature = ("T_A", "K", Some((1000.0, 50000.0))),
    ]
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_flow_stress_is_the_voce_kocks_law_and_its_slopes_are_its_derivatives() {
        // GOAL: the law as written in the module documentation, and its slopes.
        // SETUP: the illustrative constants at 77, 298 and 600 K, rates 1e-3 to 1e5 /s,
        //        strains 0, 0.01 to 1. REFERENCE: the law with libm's functions; central
        //        differences (relative steps 1e-6) within 1e-6 of the derivative's scale.
        let m = VoceKocks::ILLUSTRATIVE;
        m.validate().unwrap();
        for &t in &[77.0, 298.0, 600.0] {
            for &rate in &[1e-3, 1.0, 1e3, 1e5] {
                for &eps in &[0.0, 0.01, 0.1, 1.0] {
                    let s = 800e6 * libm::pow(rate / 1e7, t / 6000.0);
                    let expected = s - (s - 50e6) * libm::exp(-2.4e9 * eps / s);
                    let f = m.flow_stress(eps, rate, t);
                    assert!((f.value / expected - 1.0).abs() < 1e-13, "{f:?} {expected}");
                    if eps > 0.0 {
                        let h = 1e-6 * eps;
                        let d_eps = (m.flow_stress(eps + h, rate, t).value
                            - m.flow_stress(eps - h, rate, t).value)
                            / (2.0 * h);
                        assert!(
                            (f.d_plastic_strain - d_eps).abs() <= 1e-6 * d_eps.abs().max(1e6),
                            "{t} {rate} {eps}: {} vs {d_eps}",
                            f.d_plastic_strain
                        );
                    }
                    let k = 1e-6 * rate;
                    let d_rate = (m.flow_stress(eps, rate + k, t).value
                        - m.flow_stress(eps, rate - k, t).value)
                        / (2.0 * k);
                    assert!(
                        (f.d_rate - d_rate).abs() * rate <= 1e-6 * f.value,
                        "{t} {rate} {eps}: {} vs {d_rate}",
                        f.d_rate
                    );
                }
            }
        }
    }

    #[test]
    fn the_saturation_rises_with_rate_and_falls_with_temperature() {
        // GOAL: Kocks' saturation law's direction. SETUP: strain 2 (saturated), 298 K at 1e-3
        //        and 1e3 /s, 1e3 /s at 298 and 600 K. REFERENCE: higher at the higher rate,
        //        lower at the higher temperature, and at rest equal to the rate floor's.
        let m = VoceKocks::ILLUSTRATIVE;
        let at = |rate: f64, t: f64| m.flow_stress(2.0, rate, t).value;
        assert!(at(1e3, 298.0) > at(1e-3, 298.0));
        assert!(at(1e3, 600.0) < at(1e3, 298.0));
        assert_eq!(at(0.0, 298.0), at(VoceKocks::MINIMUM_RATE, 298.0));
    }

    #[test]
    fn extreme_constants_keep_finite_slopes() {
        // GOAL: the fuzzer's reproducer (fuzz/regressions/strength_update_vk/): a yield and a
        //       saturation stress at the smallest normal double under a 5 GPa hardening
        //       modulus at 2100 K; `k = theta_0 eps / sigma_s` overflowed, `e^-k` underflowed,
        //       and `0 * inf` made the rate slope (and the consistent tangent) not a number.
        // SETUP: those constants, plastic strains 0 to 1, rates 1e-6 to 1e8 /s, and a
        //        subnormal yield stress (the saturation's floor would have been zero).
        // REFERENCE: every value and slope finite; the rate slope's limit where `e^-k`
        //            underflows is `d sigma / d sigma_s = 1` times the saturation's slope.
        for yield_stress in [f64::MIN_POSITIVE, 5e-324, 2.0e-310] {
            let m = VoceKocks {
                yield_stress,
                initial_hardening: 5193587868.111053,
                saturation_stress: f64::MIN_POSITIVE,
                saturation_reference_rate: 5654668.876892094,
                activation_temperature: 1000.0,
            };
            m.validate().unwrap();
            for &eps in &[0.0, 1e-8, 0.05, 1.0] {
                for &rate in &[1e-6, 1.0, 1.07e6, 1e8] {
                    for &t in &[0.0, 298.0, 2100.0] {
                        let f = m.flow_stress(eps, rate, t);
                        assert!(
                            f.value.is_finite()
                                && f.d_plastic_strain.is_finite()
                                && f.d_rate.is_finite(),
                            "{yield_stress:e} {eps} {rate} {t}: {f:?}"
                        );
                    }
                }
            }
        }
    }
}
