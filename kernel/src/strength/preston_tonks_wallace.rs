//! Preston-Tonks-Wallace model (Preston, Tonks & Wallace, J. Appl. Phys. 93 (2003) 211-220):
//! a flow stress scaled by the shear modulus that spans thermally activated glide and, at
//! strain rates near the atomic vibration frequency, the overdriven shock regime.
//!
//! With `T^ = T / Tm`, `G(T) = G0 (1 - alpha T^)` (PTW eq. 15), the atomic vibration rate
//! `xi' = (1/2) (4 pi rho / 3 m)^(1/3) (G / rho)^(1/2)` (`m` the atomic mass) and
//! `u = deps_p / (gamma xi')`:
//!
//! - saturation stress `s^ = max(s0 - (s0 - s_inf) erf(kappa T^ ln(1/u)), s0 u^beta)` (eq. 11),
//! - yield stress `y^ = max(y0 - (y0 - y_inf) erf(kappa T^ ln(1/u)), min(y1 u^y2, s0 u^beta))`
//!   (eq. 12),
//! - hardening (eq. 7) `t^ = s^ + (s0 - y^)/p ln(1 - (1 - exp(-x)) exp(-theta psi / ((s0 -
//!   y^)/p (exp(x) - 1))))`, `x = p (s^ - y^) / (s0 - y^)`; for `p = 0` its limit
//!   `t^ = s^ - (s^ - y^) exp(-theta psi / (s^ - y^))`,
//! - the von Mises flow stress `sigma_y = 2 G(T) t^` (PTW's convention `sigma = 2 tau`).
//!
//! `psi` is the equivalent plastic strain. Simplifications, named: the density in `xi'` and
//! the melting temperature are constants (PTW let both follow the compression), and `G(T)`
//! scales only the flow stress (the material's elastic shear modulus stays its own constant).
//! `T^` is clamped to `[0, 1]`. Below [`PrestonTonksWallace::MINIMUM_RATE`] the rate is held
//! at that floor, so the zero-rate (elastic-check) flow stress is finite and continuous.
//!
//! Along a return path the flow stress's first derivative is exact; its second and third are
//! reported unbounded (`+inf`), so the return mapping converges by safeguarded Newton steps
//! alone and never accepts a third-order-corrected step (the regime switches of `max`/`min`
//! make those derivatives discontinuous anyway).

use super::FlowStress;
use crate::error::{check, ParameterError};
use crate::math::{clamp, erf, exp, expm1, ln, ln_1p, pow, sqrt};
use crate::parameters;

/// Preston-Tonks-Wallace constants (SI; the scaled stresses are dimensionless).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct PrestonTonksWallace {
    /// `theta` (-), initial hardening rate of the scaled stress.
    pub theta: f64,
    /// `p` (-), shape of the approach to saturation (0: Voce-like).
    pub p: f64,
    /// `s0` (-), scaled saturation stress at 0 K.
    pub s0: f64,
    /// `s_inf` (-), scaled saturation stress at high temperature.
    pub s_inf: f64,
    /// `kappa` (-), temperature scale of the thermal activation.
    pub kappa: f64,
    /// `gamma` (-), rate scale of the thermal activation.
    pub gamma: f64,
    /// `y0` (-), scaled yield stress at 0 K.
    pub y0: f64,
    /// `y_inf` (-), scaled yield stress at high temperature.
    pub y_inf: f64,
    /// `y1` (-), overdriven yield stress coefficient.
    pub y1: f64,
    /// `y2` (-), overdriven yield stress exponent.
    pub y2: f64,
    /// `beta` (-), overdriven saturation exponent.
    pub beta: f64,
    /// `G0` (Pa), shear modulus at 0 K.
    pub shear_modulus_0: f64,
    /// `alpha` (-), linear softening of the shear modulus with `T^`.
    pub alpha: f64,
    /// `Tm` (K), melting temperature.
    pub melting_temperature: f64,
    /// `rho` (kg/m^3), density in the vibration rate.
    pub density: f64,
    /// `M` (g/mol = atomic mass units), atomic mass.
    pub atomic_mass: f64,
}

/// A scaled stress and its derivative in the plastic strain rate.
#[derive(Clone, Copy, Debug)]
struct Scaled {
    value: f64,
    d_rate: f64,
}

impl Scaled {
    /// The larger of two (the first on a tie).
    fn max(self, other: Scaled) -> Scaled {
        if other.value > self.value {
            other
        } else {
            self
        }
    }

    /// The smaller of two (the first on a tie).
    fn min(self, other: Scaled) -> Scaled {
        if other.value < self.value {
            other
        } else {
            self
        }
    }
}

/// The hardened scaled stress `t^` and its partial derivatives in `psi`, `s^` and `y^`.
#[derive(Clone, Copy, Debug)]
struct Hardened {
    value: f64,
    d_strain: f64,
    d_saturation: f64,
    d_yield: f64,
}

impl PrestonTonksWallace {
    /// Floor of the plastic strain rate (1/s) in the activation term: below it the flow stress
    /// is that at the floor (PTW's `ln(1/u)` is unbounded at rest).
    pub const MINIMUM_RATE: f64 = 1e-8;

    /// The atomic mass unit (kg), CODATA 2018.
    pub const ATOMIC_MASS_UNIT: f64 = 1.660_539_066_60e-27;

    /// Preston, Tonks & Wallace (2003) table II, tantalum: theta 0.02, p 0, s0 0.012, s_inf
    /// 0.00325, kappa 0.6, gamma 4e-5, y0 0.01, y_inf 0.00125, y1 0.012, y2 0.4, beta 0.23,
    /// G0 72.2 GPa, alpha 0.23, rho 16.75 g/cm^3, M 180.948; Tm 3290 K (tantalum's melting
    /// point). Public copies: Uintah `PTWPlasticTa.xml`, F_UNCLE `Ptw.py`.
    pub const TANTALUM: PrestonTonksWallace = PrestonTonksWallace {
        theta: 0.02,
        p: 0.0,
        s0: 0.012,
        s_inf: 0.00325,
        kappa: 0.6,
        gamma: 4.0e-5,
        y0: 0.01,
        y_inf: 0.00125,
        y1: 0.012,
        y2: 0.4,
        beta: 0.23,
        shear_modulus_0: 72.2e9,
        alpha: 0.23,
        melting_temperature: 3290.0,
        density: 16750.0,
        atomic_mass: 180.948,
    };

    /// Preston, Tonks & Wallace (2003) table II, copper: theta 0.025, p 2, s0 0.0085, s_inf
    /// 0.00055, kappa 0.11, gamma 1e-5, y0 = y_inf 1e-4, y1 0.094, y2 0.575, beta 0.25, G0
    /// 51.8 GPa, alpha 0.20, rho 8.933 g/cm^3; Tm 1358 K (copper's melting point) and M
    /// 63.546 (copper's atomic mass; the F_UNCLE copy of the table prints 64.54). Public copy:
    /// F_UNCLE `Ptw.py`. The family's `p > 0` case in the checks.
    pub const COPPER: PrestonTonksWallace = PrestonTonksWallace {
        theta: 0.025,
        p: 2.0,
        s0: 0.0085,
        s_inf: 0.00055,
        kappa: 0.11,
        gamma: 1.0e-5,
        y0: 0.0001,
        y_inf: 0.0001,
        y1: 0.094,
        y2: 0.575,
        beta: 0.25,
        shear_modulus_0: 51.8e9,
        alpha: 0.20,
        melting_temperature: 1358.0,
        density: 8933.0,
        atomic_mass: 63.546,
    };

    /// `G(T) = G0 (1 - alpha T^)` (Pa).
    #[inline]
    pub fn shear_modulus(&self, temperature: f64) -> f64 {
        let homologous = clamp(temperature / self.melting_temperature, 0.0, 1.0);
        self.shear_modulus_0 * (1.0 - self.alpha * homologous)
    }

    /// The atomic vibration rate `xi' = (1/2) (4 pi rho / 3 m)^(1/3) (G / rho)^(1/2)` (1/s)
    /// at shear modulus `shear_modulus`.
    #[inline]
    pub fn vibration_rate(&self, shear_modulus: f64) -> f64 {
        let atom = self.atomic_mass * Self::ATOMIC_MASS_UNIT;
        let number_density = 4.0 * core::f64::consts::PI * self.density / (3.0 * atom);
        0.5 * pow(number_density, 1.0 / 3.0) * sqrt(shear_modulus / self.density)
    }

    /// The rate scale `gamma xi'(G(T))` (1/s) of `u = deps_p / (gamma xi')`: temperature only,
    /// so the return mapping evaluates it once per step ([`super::Strength::at_temperature`]).
    #[inline]
    pub fn rate_scale(&self, temperature: f64) -> f64 {
        self.gamma * self.vibration_rate(self.shear_modulus(temperature))
    }

    /// `G(T)`, the scaled saturation stress `s^` and the scaled yield stress `y^` with their
    /// rate derivatives (0 below the rate floor), given the rate scale `gamma xi'`.
    #[inline]
    fn limits(
        &self,
        plastic_strain_rate: f64,
        temperature: f64,
        rate_scale: f64,
    ) -> (f64, Scaled, Scaled) {
        let homologous = clamp(temperature / self.melting_temperature, 0.0, 1.0);
        let shear_modulus = self.shear_modulus_0 * (1.0 - self.alpha * homologous);
        let (rate, active) = super::floored_rate(plastic_strain_rate, Self::MINIMUM_RATE);
        let u = rate / rate_scale;
        let argument = -self.kappa * homologous * ln(u);
        let activation = erf(argument);
        // d erf(a)/d rate = (2/sqrt(pi)) exp(-a^2) da/drate, da/drate = -kappa T^ / rate.
        let d_activation = if active {
            -core::f64::consts::FRAC_2_SQRT_PI * exp(-argument * argument) * self.kappa * homologous
                / rate
        } else {
            0.0
        };
        let on = |slope: f64| if active { slope } else { 0.0 };
        let glide_saturation = Scaled {
            value: self.s0 - (self.s0 - self.s_inf) * activation,
            d_rate: -(self.s0 - self.s_inf) * d_activation,
        };
        let glide_yield = Scaled {
            value: self.y0 - (self.y0 - self.y_inf) * activation,
            d_rate: -(self.y0 - self.y_inf) * d_activation,
        };
        let shock_saturation_value = self.s0 * pow(u, self.beta);
        let shock_saturation = Scaled {
            value: shock_saturation_value,
            d_rate: on(self.beta * shock_saturation_value / rate),
        };
        let jump_value = self.y1 * pow(u, self.y2);
        let shock_yield = Scaled {
            value: jump_value,
            d_rate: on(self.y2 * jump_value / rate),
        }
        .min(shock_saturation);
        (
            shear_modulus,
            glide_saturation.max(shock_saturation),
            glide_yield.max(shock_yield),
        )
    }

    /// The hardening law (PTW eq. 7, or its `p = 0` limit) at plastic strain `psi`.
    #[inline]
    fn hardened(&self, saturation: f64, yield_stress: f64, psi: f64) -> Hardened {
        let psi = if psi > 0.0 { psi } else { 0.0 };
        let span = saturation - yield_stress;
        if span <= 0.0 {
            return Hardened {
                value: saturation,
                d_strain: 0.0,
                d_saturation: 1.0,
                d_yield: 0.0,
            };
        }
        let headroom = self.s0 - yield_stress;
        // The p -> 0 limit also where p is so small against (s0 - y^)/(s^ - y^) that
        // A = (s0 - y^)/p would overflow (eq. 7 and its limit then agree to 1e-12).
        if headroom <= 0.0 || self.p * span <= 1e-12 * headroom {
            // t^ = s^ - (s^ - y^) exp(-k) = y^ - (s^ - y^) expm1(-k), k = theta psi / (s^ - y^):
            // the second form has no cancellation where t^ is near y^ (small strain).
            let k = self.theta * psi / span;
            let e = exp(-k);
            return Hardened {
                value: yield_stress - span * expm1(-k),
                d_strain: self.theta * e,
                d_saturation: 1.0 - e * (1.0 + k),
                d_yield: e * (1.0 + k),
            };
        }
        // Eq. 7 with A = (s0 - y^)/p, x = (s^ - y^)/A, C = e^x - 1, E = theta / (A C),
        // rearranged without cancellation: s^ + A ln(1 - (1 - e^-x) e^(-E psi)) = y^ + A ln(1 +
        // C m), m = 1 - e^(-E psi) (both sides: A ln(e^x (1 - (1 - e^-x) e^(-E psi)))).
        let a = headroom / self.p;
        let x = span / a;
        let c = expm1(x);
        let e = self.theta / (a * c);
        let q = exp(-e * psi);
        let m = -expm1(-e * psi);
        let v = 1.0 + c * m;
        let log_v = ln_1p(c * m);
        // Partials in s^ (A fixed) and y^ (A moves too), each through C (via x), E and m.
        let partial = |a_prime: f64, x_prime: f64| {
            let c_prime = (c + 1.0) * x_prime;
            let e_prime = -e * (a_prime / a + c_prime / c);
            let m_prime = psi * q * e_prime;
            a_prime * log_v + a * (c_prime * m + c * m_prime) / v
        };
        Hardened {
            value: yield_stress + a * log_v,
            d_strain: a * c * e * q / v,
            d_saturation: partial(0.0, 1.0 / a),
            d_yield: 1.0
                + partial(
                    -1.0 / self.p,
                    self.p * (saturation - self.s0) / (headroom * headroom),
                ),
        }
    }

    /// Flow stress and its strain and rate derivatives at fixed temperature.
    #[inline]
    pub fn flow_stress(
        &self,
        plastic_strain: f64,
        plastic_strain_rate: f64,
        temperature: f64,
    ) -> FlowStress {
        let scale = self.rate_scale(temperature);
        self.flow_stress_at_rate_scale(plastic_strain, plastic_strain_rate, temperature, scale)
    }

    /// [`Self::flow_stress`] with its rate scale ([`Self::rate_scale`]) already evaluated.
    #[inline]
    pub fn flow_stress_at_rate_scale(
        &self,
        plastic_strain: f64,
        plastic_strain_rate: f64,
        temperature: f64,
        rate_scale: f64,
    ) -> FlowStress {
        let (shear_modulus, saturation, yield_stress) =
            self.limits(plastic_strain_rate, temperature, rate_scale);
        let h = self.hardened(saturation.value, yield_stress.value, plastic_strain);
        let scale = 2.0 * shear_modulus;
        FlowStress {
            value: scale * h.value,
            d_plastic_strain: scale * h.d_strain,
            d_rate: scale * (h.d_saturation * saturation.d_rate + h.d_yield * yield_stress.d_rate),
        }
    }

    /// Reject non-physical constants: positive scales, `y_inf <= y0 <= s0`, `y_inf <= s_inf
    /// <= s0` (so that the glide yield stress never exceeds the glide saturation stress),
    /// `alpha < 1` (a positive shear modulus up to melting).
    pub fn validate(&self) -> Result<(), ParameterError> {
        check::non_negative("theta", self.theta)?;
        check::non_negative("p", self.p)?;
        check::positive("s0", self.s0)?;
        check::positive("s_inf", self.s_inf)?;
        check::non_negative("kappa", self.kappa)?;
        check::positive("gamma", self.gamma)?;
        check::positive("y0", self.y0)?;
        check::positive("y_inf", self.y_inf)?;
        check::non_negative("y1", self.y1)?;
        check::non_negative("y2", self.y2)?;
        check::non_negative("beta", self.beta)?;
        check::positive("shear_modulus_0", self.shear_modulus_0)?;
        check::range("alpha", self.alpha, 0.0, 0.999)?;
        check::positive("melting_temperature", self.melting_temperature)?;
        check::positive("density", self.density)?;
        check::positive("atomic_mass", self.atomic_mass)?;
        check::range("s_inf", self.s_inf, 0.0, self.s0)?;
        check::range("y0", self.y0, 0.0, self.s0)?;
        check::range("y_inf", self.y_inf, 0.0, self.y0.min(self.s_inf))?;
        Ok(())
    }
}

// Search ranges: PTW (2003) table II spans theta 0.014-0.055, p 0-10, s0 0.007-0.05, s_inf
// 0.00015-0.0075, kappa 0.11-0.6, gamma 8e-6-2e-3, y0 1e-4-0.0125, y_inf 1e-4-0.0023, y1
// 0.007-0.094, y2 0.25-0.575, beta 0.23-0.25 over Cu, U, Ta, V, Mo, Be and two steels; the
// ranges bracket those. The modulus, melting point, density and atomic mass are measured, not
// fitted.
crate::struct_constants!(
    PrestonTonksWallace,
    [
        theta = ("theta", "-", Some((0.005, 0.1))),
        p = ("p", "-", Some((0.0, 10.0))),
        s0 = ("s0", "-", Some((0.002, 0.06))),
        s_inf = ("s_inf", "-", Some((1.0e-4, 0.01))),
        kappa = ("kappa", "-", Some((0.05, 1.0))),
        gamma = ("gamma", "-", Some((1.0e-6, 5.0e-3))),
        y0 = ("y0", "-", Some((1.0e-4, 0.02))),
        y_inf = ("y_inf", "-", Some((1.0e-5, 0.005))),
        y1 = ("y1", "-", Some((0.005, 0.1))),
        y2 = ("y2", "-", Some((0.2, 0.7))),
        beta = ("beta", "-", Some((0.1, 0.4))),
        shear_modulus_0 = ("G0", "Pa", parameters::FIXED),
        alpha = ("alpha", "-", parameters::FIXED),
        melting_temperature = ("Tm", "K", parameters::FIXED),
        density = ("rho", "kg/m^3", parameters::FIXED),
        atomic_mass = ("M", "g/mol", parameters::FIXED),
    ]
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_match_central_differences() {
        // GOAL: the strain and rate derivatives are those of the value.
        // SETUP: Ta (p = 0) and Cu (p = 2) at 298 and 900 K, rates 1e-3 to 1e5 /s, strains 0.01
        //        to 0.5; central differences with relative steps 1e-6.
        // REFERENCE: agreement within 1e-5 of the derivative's scale.
        for model in [PrestonTonksWallace::TANTALUM, PrestonTonksWallace::COPPER] {
            model.validate().unwrap();
            for &t in &[298.0, 900.0] {
                for &rate in &[1e-3, 1.0, 1e3, 1e5] {
                    for &eps in &[0.01, 0.1, 0.5] {
                        let f = model.flow_stress(eps, rate, t);
                        let h = 1e-6 * eps;
                        let d_eps = (model.flow_stress(eps + h, rate, t).value
                            - model.flow_stress(eps - h, rate, t).value)
                            / (2.0 * h);
                        let k = 1e-6 * rate;
                        let d_rate = (model.flow_stress(eps, rate + k, t).value
                            - model.flow_stress(eps, rate - k, t).value)
                            / (2.0 * k);
                        assert!(
                            (f.d_plastic_strain - d_eps).abs() <= 1e-5 * d_eps.abs().max(f.value),
                            "{t} K {rate} /s {eps}: {} vs {d_eps}",
                            f.d_plastic_strain
                        );
                        assert!(
                            (f.d_rate - d_rate).abs() * rate <= 1e-5 * f.value,
                            "{t} K {rate} /s {eps}: {} vs {d_rate}",
                            f.d_rate
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn tantalum_matches_a_hand_evaluation_of_the_ptw_equations() {
        // GOAL: the closed form of PTW (2003) eqs. 7, 11, 12, 15 for tantalum.
        // SETUP: Ta, 298 K, 1000 /s, plastic strain 0.1 (glide regime, p = 0).
        // REFERENCE: evaluated step by step with libm's functions (not the kernel's): T^ = 298/3290,
        //        G = 72.2e9 (1 - 0.23 T^), xi' from rho = 16750, M = 180.948 u, u = 1000 /
        //        (4e-5 xi'), a = -0.6 T^ ln u, s^ and y^ from erf(a) (glide branches),
        //        t^ = s^ - (s^ - y^) exp(-0.02 * 0.1 / (s^ - y^)), sigma = 2 G t^.
        let m = PrestonTonksWallace::TANTALUM;
        let th = 298.0_f64 / 3290.0;
        let g = 72.2e9 * (1.0 - 0.23 * th);
        let atom = 180.948 * PrestonTonksWallace::ATOMIC_MASS_UNIT;
        let xi = 0.5
            * libm::cbrt(4.0 * core::f64::consts::PI * 16750.0 / (3.0 * atom))
            * libm::sqrt(g / 16750.0);
        let u = 1000.0 / (4e-5 * xi);
        let z = libm::erf(-0.6 * th * libm::log(u));
        let s = 0.012 - (0.012 - 0.00325) * z;
        let y = 0.01 - (0.01 - 0.00125) * z;
        let t = s - (s - y) * libm::exp(-0.02 * 0.1 / (s - y));
        let expected = 2.0 * g * t;
        let got = m.flow_stress(0.1, 1000.0, 298.0).value;
        assert!((got / expected - 1.0).abs() < 1e-12, "{got} vs {expected}");
        // Tantalum's flow stress at 1000 /s and room temperature is several hundred MPa.
        assert!((3.0e8..1.0e9).contains(&got), "{got}");
    }

    #[test]
    fn the_rate_floor_holds_the_static_flow_stress_finite() {
        // GOAL: the elastic check's zero-rate flow stress is finite and equals the floor's.
        // SETUP: Ta at 298 K, strain 0.05, rates 0 and the floor. REFERENCE: equal values,
        //        zero rate derivative below the floor.
        let m = PrestonTonksWallace::TANTALUM;
        let at_rest = m.flow_stress(0.05, 0.0, 298.0);
        let at_floor = m.flow_stress(0.05, PrestonTonksWallace::MINIMUM_RATE, 298.0);
        assert!(at_rest.value.is_finite() && at_rest.value > 0.0);
        assert_eq!(at_rest.value, at_floor.value);
        assert_eq!(at_rest.d_rate, 0.0);
    }

    #[test]
    fn bad_constants_are_rejected_by_name() {
        // GOAL: validate names the field. SETUP: y0 above s0; alpha 1. REFERENCE: the names.
        let field = |m: PrestonTonksWallace| match m.validate() {
            Err(ParameterError::OutOfRange { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        let mut m = PrestonTonksWallace::TANTALUM;
        m.y0 = 0.02;
        assert_eq!(field(m), "y0");
        let mut m = PrestonTonksWallace::TANTALUM;
        m.alpha = 1.0;
        assert_eq!(field(m), "alpha");
    }
}
