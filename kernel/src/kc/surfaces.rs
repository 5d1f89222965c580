//! The K&C meridians and the current strength (Malvar et al. 1997; the low-pressure and
//! tension branches and `psi(p)` as in LS-DYNA `*MAT_072R3`, Schwer & Malvar 2005).
//!
//! All strengths are compressive-meridian values of `Delta sigma = sqrt(3 J2)` (Pa) at the
//! *rate-scaled* pressure `p/r_f` unless stated; pressures positive in compression.

use super::parameters::KcParameters;
use crate::math::sqrt;
use crate::rht::{lode_factor_from_cos, Lode};

impl KcParameters {
    /// Ratio `psi(p)` of the tensile to the compressive meridian: 1/2 in tension, rising
    /// linearly to `1/2 + 3/2 ft/fc` at uniaxial compression (`p = fc/3`), to the biaxial
    /// point's `alpha fc / Delta sigma_m(2 alpha fc/3)` at `p = 2 alpha fc/3`, to 0.753 at
    /// `p = 3 fc` and to 1 at `p = 8.45 fc`, then 1.
    pub fn meridian_ratio(&self, pressure: f64) -> f64 {
        let fc = self.compressive_strength;
        let uniaxial = 0.5 + 1.5 * self.tensile_strength / fc;
        let biaxial_pressure = 2.0 * self.biaxial_ratio * fc / 3.0;
        // The biaxial point lies above fc/3 (biaxial ratio >= 1): the maximum surface's
        // formula directly (never through this function again, whatever the constants).
        let [a0, a1, a2] = self.maximum_surface;
        let biaxial =
            self.biaxial_ratio * fc / (a0 + biaxial_pressure / (a1 + a2 * biaxial_pressure));
        let line =
            |p0: f64, r0: f64, p1: f64, r1: f64| r0 + (r1 - r0) * (pressure - p0) / (p1 - p0);
        if pressure <= 0.0 {
            0.5
        } else if pressure <= fc / 3.0 {
            line(0.0, 0.5, fc / 3.0, uniaxial)
        } else if pressure <= biaxial_pressure {
            line(fc / 3.0, uniaxial, biaxial_pressure, biaxial)
        } else if pressure <= 3.0 * fc {
            line(biaxial_pressure, biaxial, 3.0 * fc, 0.753)
        } else if pressure < 8.45 * fc {
            line(3.0 * fc, 0.753, 8.45 * fc, 1.0)
        } else {
            1.0
        }
    }

    /// Maximum (failure) surface, compressive meridian: `a0 + p/(a1 + a2 p)` from
    /// `p = fc/3`; below, the tensile meridian is the line `3/2 (p + ft)` through uniaxial
    /// tension and the compressive one is it over `psi(p)`; zero at `p = -ft` and below.
    pub fn maximum_meridian(&self, pressure: f64) -> f64 {
        let fc = self.compressive_strength;
        let ft = self.tensile_strength;
        let [a0, a1, a2] = self.maximum_surface;
        if pressure >= fc / 3.0 {
            a0 + pressure / (a1 + a2 * pressure)
        } else if pressure >= 0.0 {
            1.5 * (pressure + ft) / self.meridian_ratio(pressure)
        } else {
            let strength = 3.0 * (pressure + ft);
            if strength > 0.0 {
                strength
            } else {
                0.0
            }
        }
    }

    /// The uniaxial compressive strength at the yield surface, `fyc` with
    /// `a0y + (fyc/3)/(a1y + a2y fyc/3) = fyc` (the positive root of a quadratic).
    pub fn yield_uniaxial_strength(&self) -> f64 {
        let [a0, a1, a2] = self.yield_surface;
        // x = fyc/3: 3 a2 x^2 + (3 a1 - a0 a2 - 1) x - a0 a1 = 0.
        let b = 3.0 * a1 - a0 * a2 - 1.0;
        let x = if a2 > 0.0 {
            (-b + sqrt(b * b + 12.0 * a2 * a0 * a1)) / (6.0 * a2)
        } else {
            a0 * a1 / b
        };
        3.0 * x
    }

    /// Yield surface, compressive meridian: `a0y + p/(a1y + a2y p)` from `p = fyc/3`; the line
    /// `1.35 ft + 3 p (1 - 1.35 ft/fyc)` from `p = 0` to there; `1.35 (p + ft)` in tension;
    /// never above the maximum surface.
    pub fn yield_meridian(&self, pressure: f64) -> f64 {
        self.yield_meridian_below(pressure, self.maximum_meridian(pressure))
    }

    /// [`KcParameters::yield_meridian`] with the maximum surface at `pressure` given.
    fn yield_meridian_below(&self, pressure: f64, maximum: f64) -> f64 {
        let ft = self.tensile_strength;
        let fyc = self.yield_uniaxial_strength();
        let [a0, a1, a2] = self.yield_surface;
        let strength = if pressure >= fyc / 3.0 {
            a0 + pressure / (a1 + a2 * pressure)
        } else if pressure >= 0.0 {
            1.35 * ft + 3.0 * pressure * (1.0 - 1.35 * ft / fyc)
        } else {
            1.35 * (pressure + ft)
        };
        let strength = if strength < maximum {
            strength
        } else {
            maximum
        };
        if strength > 0.0 {
            strength
        } else {
            0.0
        }
    }

    /// Residual surface, compressive meridian: `p/(a1f + a2f p)` in compression, zero in
    /// tension, never above the maximum surface.
    pub fn residual_meridian(&self, pressure: f64) -> f64 {
        self.residual_meridian_below(pressure, self.maximum_meridian(pressure))
    }

    /// [`KcParameters::residual_meridian`] with the maximum surface at `pressure` given.
    fn residual_meridian_below(&self, pressure: f64, maximum: f64) -> f64 {
        if pressure <= 0.0 {
            return 0.0;
        }
        let [a1, a2] = self.residual_surface;
        let strength = pressure / (a1 + a2 * pressure);
        if strength < maximum {
            strength
        } else {
            maximum
        }
    }

    /// The strengths at one pressure, Lode angle and rate factor, for the return: the
    /// current strength is `base + eta span` with the pre- or post-peak pair (see
    /// [`Strengths`]).
    pub fn strengths(&self, pressure: f64, lode: Lode, rate_factor: f64) -> Strengths {
        let scaled = pressure / rate_factor;
        let factor =
            rate_factor * lode_factor_from_cos(lode.cos_theta, self.meridian_ratio(scaled));
        // The maximum surface once, for the three meridians.
        let maximum = self.maximum_meridian(scaled);
        let yield_ = self.yield_meridian_below(scaled, maximum);
        let (post_base, post_span) = if scaled >= 0.0 {
            let residual = self.residual_meridian_below(scaled, maximum);
            (residual, maximum - residual)
        } else {
            // In tension the softened surface is the maximum one scaled about the origin by
            // eta: 3 (p + eta ft), zero at p = -eta ft.
            (3.0 * scaled, 3.0 * self.tensile_strength)
        };
        Strengths {
            pre_base: factor * yield_,
            pre_span: factor * (maximum - yield_),
            post_base: factor * post_base,
            post_span: factor * post_span,
        }
    }
}

/// The current strength at fixed pressure, Lode angle and rate factor (Pa, `sqrt(3 J2)`):
/// `pre_base + eta pre_span` before the peak (yield to maximum surface, eta rising),
/// `post_base + eta post_span` after it (maximum to residual surface, eta falling), never
/// negative.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Strengths {
    /// Yield surface.
    pub pre_base: f64,
    /// Maximum minus yield surface.
    pub pre_span: f64,
    /// Residual surface (in tension `3 p`).
    pub post_base: f64,
    /// Maximum minus residual surface (in tension `3 ft`).
    pub post_span: f64,
}

impl Strengths {
    /// The strength at `eta`, before (`post_peak = false`) or after the peak.
    pub fn at(&self, eta: f64, post_peak: bool) -> f64 {
        let strength = self.linear(eta, post_peak);
        if strength > 0.0 {
            strength
        } else {
            0.0
        }
    }

    /// [`Strengths::at`] before the clamp at zero: linear in `eta` (negative where the
    /// softened tensile surface has closed).
    pub fn linear(&self, eta: f64, post_peak: bool) -> f64 {
        if post_peak {
            self.post_base + eta * self.post_span
        } else {
            self.pre_base + eta * self.pre_span
        }
    }
}
