//! The RHT strength surfaces and their factors (seed 001 eqs. 4.1-4.9), evaluated directly
//! so that tests and hosts can compare a stress history with the equations.
//!
//! All strengths are von Mises equivalent stresses `sigma_eq = sqrt(3 J2)` in Pa; pressures
//! are in Pa, positive in compression; `p* = p / fc`.

use super::parameters::{FailureMeridian, RateScaling, RhtParameters};
use crate::math::{clamp, pow, sqrt};
use crate::tensor::{self, Sym};

/// `cos(pi/6)`: the pure-shear meridian (`J3 = 0`, Lode angle `pi/6`).
pub const COS_SHEAR_MERIDIAN: f64 = 0.866_025_403_784_438_6;

/// The Lode angle `theta` in `[0, pi/3]`, with `cos 3 theta = (3 sqrt(3)/2) J3 / J2^(3/2)`:
/// `theta = 0` on the tensile meridian (uniaxial tension, `R3 = Q2`), `theta = pi/3` on the
/// compressive meridian (uniaxial compression, `R3 = 1`). Stored as `cos theta` in
/// `[1/2, 1]`, which is what eq. 4.2 needs.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Lode {
    /// `cos theta`, in `[1/2, 1]`.
    pub cos_theta: f64,
}

impl Lode {
    /// Compressive meridian (`theta = pi/3`, uniaxial compression, triaxial compression).
    pub const COMPRESSIVE_MERIDIAN: Lode = Lode { cos_theta: 0.5 };
    /// Tensile meridian (`theta = 0`, uniaxial tension, triaxial extension).
    pub const TENSILE_MERIDIAN: Lode = Lode { cos_theta: 1.0 };
    /// Shear meridian (`theta = pi/6`, pure shear).
    pub const SHEAR_MERIDIAN: Lode = Lode {
        cos_theta: COS_SHEAR_MERIDIAN,
    };

    /// From the angle `theta` (radians), clamped to `[0, pi/3]`.
    pub fn from_angle(theta: f64) -> Self {
        let theta = clamp(theta, 0.0, core::f64::consts::FRAC_PI_3);
        Lode {
            cos_theta: libm::cos(theta),
        }
    }

    /// The Lode angle of a deviator; a zero deviator is put on the compressive meridian.
    pub fn from_deviator(deviator: &Sym) -> Self {
        // cos 3theta is scale-invariant: normalise by the largest component first, so that
        // J2 and J3 of tiny (or huge) deviators neither underflow nor overflow.
        let scale = deviator.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        if !(scale.is_finite() && scale > 0.0) {
            return Self::COMPRESSIVE_MERIDIAN;
        }
        // Division (not multiplication by 1/scale) keeps the largest component exactly +-1.
        let s: &Sym = &core::array::from_fn(|i| deviator[i] / scale);
        let j2 = 0.5 * tensor::contract(s, s);
        if j2.is_nan() || j2 <= 0.0 {
            return Self::COMPRESSIVE_MERIDIAN;
        }
        let j3 = s[0] * (s[1] * s[2] - s[4] * s[4]) - s[3] * (s[3] * s[2] - s[4] * s[5])
            + s[5] * (s[3] * s[4] - s[1] * s[5]);
        let cos_3theta = clamp(1.5 * sqrt(3.0) * j3 / (j2 * sqrt(j2)), -1.0, 1.0);
        // libm directly: kernel/src/math.rs has no inverse trigonometric functions.
        Lode {
            cos_theta: libm::cos(libm::acos(cos_3theta) / 3.0),
        }
    }

    /// Largest principal value of a deviator with von Mises equivalent `q` and this Lode
    /// angle: `s1 = (2/3) q cos theta`.
    #[inline]
    pub fn largest_principal_deviator(&self, equivalent: f64) -> f64 {
        2.0 / 3.0 * equivalent * self.cos_theta
    }
}

/// Willam-Warnke deviatoric factor, seed eq. 4.2, from `cos theta` and `Q = Q2`:
/// `R3 = [2(1-Q^2) c + (2Q-1) sqrt(4(1-Q^2)c^2 + 5Q^2 - 4Q)] / [4(1-Q^2)c^2 + (1-2Q)^2]`.
/// `R3 = Q` at `c = 1` (tensile meridian), `R3 = 1` at `c = 1/2` (compressive meridian).
pub fn lode_factor_from_cos(cos_theta: f64, q: f64) -> f64 {
    let c = cos_theta;
    let one_minus_q2 = 1.0 - q * q;
    let radicand = 4.0 * one_minus_q2 * c * c + 5.0 * q * q - 4.0 * q;
    let radicand = if radicand > 0.0 { radicand } else { 0.0 };
    let numerator = 2.0 * one_minus_q2 * c + (2.0 * q - 1.0) * sqrt(radicand);
    let one_minus_2q = 1.0 - 2.0 * q;
    let denominator = 4.0 * one_minus_q2 * c * c + one_minus_2q * one_minus_2q;
    numerator / denominator
}

impl RhtParameters {
    /// Lode factor `R3(theta, Q2(p*))`, eqs. 4.2-4.3, at pressure `pressure` (Pa).
    pub fn lode_factor(&self, lode: Lode, pressure: f64) -> f64 {
        let q2 = self.tensile_meridian_ratio_at(pressure / self.compressive_strength);
        lode_factor_from_cos(lode.cos_theta, q2)
    }

    /// Rate factor `F_rate`, eq. 4.4 (restored): with the strain rate `rate`
    /// (1/s), `F_c = (rate/rate0_c)^alpha` for `p >= fc/3`, `F_t = (rate/rate0_t)^delta`
    /// for `p <= -ft/3`, linear in pressure between; never below 1.
    pub fn rate_factor(&self, rate: f64, pressure: f64) -> f64 {
        let (compression, tension) = self.rate_factors(rate);
        let upper = self.compressive_strength / 3.0;
        let lower = -self.tensile_strength() / 3.0;
        if pressure >= upper {
            compression
        } else if pressure <= lower {
            tension
        } else {
            tension + (compression - tension) * (pressure - lower) / (upper - lower)
        }
    }

    /// The compressive and tensile branches of the rate factor, `(F_c, F_t)`, each `>= 1`.
    pub fn rate_factors(&self, rate: f64) -> (f64, f64) {
        let branch = |reference: f64, exponent: f64| {
            let ratio = rate / reference;
            if ratio > 1.0 {
                pow(ratio, exponent)
            } else {
                1.0
            }
        };
        (
            branch(
                self.compressive_reference_rate,
                self.compressive_rate_exponent,
            ),
            branch(self.tensile_reference_rate, self.tensile_rate_exponent),
        )
    }

    /// Quasi-static compressive meridian `g(p*) = Y*_TXC(p*)` at `F_rate = 1` (normalised by
    /// `fc`), eq. 4.1 with the restorations of [`crate::rht`]: `g(1/3) = 1` always; zero
    /// below `p*_spall`.
    pub fn compressive_meridian(&self, p_star: f64) -> f64 {
        let power_law = |p: f64| {
            let shifted = p - self.power_law_intercept();
            if shifted > 0.0 {
                self.failure_a * pow(shifted, self.failure_n)
            } else {
                0.0
            }
        };
        match self.meridian {
            FailureMeridian::PowerLaw => power_law(p_star),
            FailureMeridian::CharacteristicPoints => {
                if p_star >= 1.0 / 3.0 {
                    return power_law(p_star);
                }
                let g_s = self.shear_point();
                if p_star >= 0.0 {
                    g_s + 3.0 * p_star * (1.0 - g_s)
                } else {
                    let g_t = self.tension_point();
                    let g = g_s + 3.0 * p_star * (g_s - g_t) / self.tensile_strength_ratio;
                    if g > 0.0 {
                        g
                    } else {
                        0.0
                    }
                }
            }
        }
    }

    /// Failure surface `Y_fail(p, theta, F)` (Pa), eqs. 4.1-4.5:
    /// `fc F^(1+k) R3(theta, Q2(p*)) g(p*/F)`, `k = N` for [`RateScaling::SeedEquation`]
    /// (which is exactly `fc F A (p* - p*_spall F)^N R3` on the power-law branch) and
    /// `k = 0` for [`RateScaling::Homothetic`].
    pub fn failure_strength(&self, pressure: f64, lode: Lode, rate_factor: f64) -> f64 {
        let fc = self.compressive_strength;
        let scale = match self.rate_scaling {
            RateScaling::SeedEquation => pow(rate_factor, 1.0 + self.failure_n),
            RateScaling::Homothetic => rate_factor,
        };
        fc * scale
            * self.lode_factor(lode, pressure)
            * self.compressive_meridian(pressure / (fc * rate_factor))
    }

    /// Elastic scaling `F_e(p*)`: `COMPRAT` at and above `p* = COMPRAT F/3`, `TENSRAT` at and
    /// below `p* = -TENSRAT FT* F/3`, linear between.
    pub fn elastic_scaling(&self, pressure: f64, rate_factor: f64) -> f64 {
        let p_star = pressure / self.compressive_strength;
        let comprat = self.compressive_elastic_ratio;
        let tensrat = self.tensile_elastic_ratio;
        let upper = comprat * rate_factor / 3.0;
        let lower = -tensrat * self.tensile_strength_ratio * rate_factor / 3.0;
        if p_star >= upper {
            comprat
        } else if p_star <= lower {
            tensrat
        } else {
            tensrat + (comprat - tensrat) * (p_star - lower) / (upper - lower)
        }
    }

    /// Cap factor `F_cap(p)`: 1 up to `p_u = COMPRAT fc/3`, the quarter ellipse
    /// `sqrt(1 - ((p - p_u)/(p_0 - p_u))^2)` between, 0 from the pore-crush pressure
    /// `p_0 = cap_pressure` on. `None` (or [`RhtParameters::elastic_cap`] false): 1.
    pub fn cap_factor(&self, pressure: f64, cap_pressure: Option<f64>) -> f64 {
        let Some(p0) = cap_pressure.filter(|_| self.elastic_cap) else {
            return 1.0;
        };
        let pu = self.compressive_elastic_ratio * self.compressive_strength / 3.0;
        if pressure <= pu {
            1.0
        } else if pressure >= p0 {
            0.0
        } else {
            let x = (pressure - pu) / (p0 - pu);
            sqrt(1.0 - x * x)
        }
    }

    /// Elastic limit surface (Pa): the failure surface scaled homothetically about the
    /// origin by `F_e`, times the cap, `F_e Y_fail(p/F_e) F_cap(p)`, never above
    /// `Y_fail(p)`. The homothety keeps the uniaxial paths, so the elastic limit in
    /// uniaxial compression is `COMPRAT fc` and in uniaxial tension `TENSRAT ft`.
    pub fn elastic_strength(
        &self,
        pressure: f64,
        lode: Lode,
        rate_factor: f64,
        cap_pressure: Option<f64>,
    ) -> f64 {
        let scaling = self.elastic_scaling(pressure, rate_factor);
        let scaled = scaling
            * self.failure_strength(pressure / scaling, lode, rate_factor)
            * self.cap_factor(pressure, cap_pressure);
        let failure = self.failure_strength(pressure, lode, rate_factor);
        if scaled < failure {
            scaled
        } else {
            failure
        }
    }

    /// Residual surface `Y_resid = fc B p*^M` (Pa), eq. 4.8; zero for `p <= 0`.
    pub fn residual_strength(&self, pressure: f64) -> f64 {
        let p_star = pressure / self.compressive_strength;
        if p_star > 0.0 {
            self.compressive_strength * self.residual_b * pow(p_star, self.residual_m)
        } else {
            0.0
        }
    }

    /// Plastic strain to failure `max(D1 (p* - p*_spall)^D2, EFMIN)`, eq. 4.7.
    pub fn failure_strain(&self, pressure: f64) -> f64 {
        let shifted = pressure / self.compressive_strength - self.spall_pressure_ratio();
        let strain = if shifted > 0.0 {
            self.damage_d1 * pow(shifted, self.damage_d2)
        } else {
            0.0
        };
        if strain > self.minimum_failure_strain {
            strain
        } else {
            self.minimum_failure_strain
        }
    }

    /// Plastic strain at which hardening reaches the failure surface ("pre-softening"
    /// strain): `(Y_fail - Y_el) (PREFACT - 1) / (3 G)`. With `PREFACT = G/G_ep` and `G_ep`
    /// the slope of `sigma_eq` against the total equivalent strain (`3 G_ep`), the linear
    /// hardening modulus is `H = 3G/(PREFACT - 1)`.
    pub fn pre_softening_strain(&self, failure: f64, elastic: f64) -> f64 {
        let gap = failure - elastic;
        if gap > 0.0 {
            gap * (self.shear_modulus_ratio - 1.0) / (3.0 * self.shear_modulus)
        } else {
            0.0
        }
    }

    /// Shear modulus after damage `D`: `G (1 - D + D SHRATD)`.
    #[inline]
    pub fn damaged_shear_modulus(&self, damage: f64) -> f64 {
        self.shear_modulus * (1.0 - damage + damage * self.residual_shear_modulus_ratio)
    }

    /// Hydrostatic tensile limit `p_min = F p*_spall fc (1 - D)` (Pa, `<= 0`): where the
    /// failure surface at rate factor `F` meets the pressure axis, shrinking with damage.
    pub fn hydro_tensile_limit(&self, rate_factor: f64, damage: f64) -> f64 {
        let limit =
            rate_factor * self.spall_pressure_ratio() * self.compressive_strength * (1.0 - damage);
        if limit < 0.0 {
            limit
        } else {
            0.0
        }
    }

    /// All surfaces at one pressure, Lode angle and rate factor.
    pub fn surfaces(
        &self,
        pressure: f64,
        lode: Lode,
        rate_factor: f64,
        cap_pressure: Option<f64>,
    ) -> Surfaces {
        let failure = self.failure_strength(pressure, lode, rate_factor);
        let elastic = self.elastic_strength(pressure, lode, rate_factor, cap_pressure);
        let residual = self.residual_strength(pressure);
        Surfaces {
            failure,
            elastic,
            residual: if residual < failure {
                residual
            } else {
                failure
            },
            pre_softening_strain: self.pre_softening_strain(failure, elastic),
            failure_strain: self.failure_strain(pressure),
        }
    }
}

/// The surfaces at one point of stress space.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Surfaces {
    /// Failure surface `Y_fail` (Pa).
    pub failure: f64,
    /// Elastic limit (with cap) `Y_el <= Y_fail` (Pa).
    pub elastic: f64,
    /// Residual surface, capped at the failure surface, `min(Y_resid, Y_fail)` (Pa).
    pub residual: f64,
    /// Pre-softening plastic strain (-).
    pub pre_softening_strain: f64,
    /// Plastic strain to failure (-).
    pub failure_strain: f64,
}

impl Surfaces {
    /// The current strength: damaged (`D > 0`), eq. 4.9, `(1 - D) Y_fail + D Y_resid`;
    /// hardening (`D = 0`), `Y_el + min(eps_p/eps_pre, 1) (Y_fail - Y_el)`.
    pub fn current(&self, plastic_strain: f64, damage: f64) -> f64 {
        if damage > 0.0 {
            self.failure - damage * (self.failure - self.residual)
        } else {
            let fraction = if plastic_strain >= self.pre_softening_strain {
                1.0
            } else {
                plastic_strain / self.pre_softening_strain
            };
            self.elastic + fraction * (self.failure - self.elastic)
        }
    }
}
