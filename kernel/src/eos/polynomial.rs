//! Polynomial EoS (Autodyn "Polynomial", LS-DYNA `*EOS_LINEAR_POLYNOMIAL` with the tension
//! branch of Autodyn; seed 001 eqs. 4.10a-b give the cold part):
//!
//! ```text
//! mu >= 0:  p = A1 mu + A2 mu^2 + A3 mu^3 + (B0 + B1 mu) E
//! mu <  0:  p = T1 mu + T2 mu^2           +  B0 E
//! ```
//!
//! with `mu = rho/rho0 - 1` and `E = rho0 e` the internal energy per unit reference volume.
//! Both branches give `p = B0 E` at `mu = 0`, so the pressure is continuous; the slope jumps
//! from `T1` to `A1` unless they are equal.

use super::EnergyLinearPressure;
use crate::error::{check, ParameterError};

/// Polynomial EoS constants (SI).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Polynomial {
    /// `A1` (Pa), the bulk modulus in compression.
    pub a1: f64,
    /// `A2` (Pa).
    pub a2: f64,
    /// `A3` (Pa).
    pub a3: f64,
    /// `B0` (-), energy coefficient at `mu = 0` (both branches).
    pub b0: f64,
    /// `B1` (-), energy coefficient slope in compression.
    pub b1: f64,
    /// `T1` (Pa), the bulk modulus in tension. Autodyn's "T1 = 0 means T1 = A1" shortcut is
    /// not applied: give the value.
    pub t1: f64,
    /// `T2` (Pa).
    pub t2: f64,
}

impl Polynomial {
    /// The linear EoS `p = K mu` written as a polynomial (`A1 = T1 = K`, every other constant
    /// zero): the same pressures bit for bit, and the nested starting point to which a
    /// nonlinear term (`A2`) can be added.
    pub const fn linear(bulk_modulus: f64) -> Self {
        Self {
            a1: bulk_modulus,
            a2: 0.0,
            a3: 0.0,
            b0: 0.0,
            b1: 0.0,
            t1: bulk_modulus,
            t2: 0.0,
        }
    }

    /// Energy-linear terms at compression `mu`, with exact derivatives of both polynomials.
    #[inline]
    pub fn evaluate(&self, mu: f64) -> EnergyLinearPressure {
        if mu >= 0.0 {
            EnergyLinearPressure {
                base: mu * (self.a1 + mu * (self.a2 + mu * self.a3)),
                d_base_d_mu: self.a1 + mu * (2.0 * self.a2 + 3.0 * mu * self.a3),
                energy_coefficient: self.b0 + self.b1 * mu,
                d_energy_coefficient_d_mu: self.b1,
            }
        } else {
            EnergyLinearPressure {
                base: mu * (self.t1 + mu * self.t2),
                d_base_d_mu: self.t1 + 2.0 * self.t2 * mu,
                energy_coefficient: self.b0,
                d_energy_coefficient_d_mu: 0.0,
            }
        }
    }

    /// `A1 > 0`, `T1 > 0`; the other coefficients only need to be finite.
    pub fn validate(&self) -> Result<(), ParameterError> {
        check::positive("a1", self.a1)?;
        check::finite("a2", self.a2)?;
        check::finite("a3", self.a3)?;
        check::finite("b0", self.b0)?;
        check::finite("b1", self.b1)?;
        check::positive("t1", self.t1)?;
        check::finite("t2", self.t2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eos::LinearEos;

    const SAMPLE: Polynomial = Polynomial {
        a1: 35.0e9,
        a2: 39.0e9,
        a3: 9.0e9,
        b0: 1.22,
        b1: 1.22,
        t1: 30.0e9,
        t2: 2.0e9,
    };

    #[test]
    fn reduces_to_the_linear_eos_when_only_a1_and_t1_are_set() {
        // GOAL: A1 = T1 = K, everything else zero, is the linear EoS p = K mu.
        // SETUP: K = 159 GPa, mu in compression and tension.
        // REFERENCE: LinearEos terms; tolerance: bit-for-bit (same arithmetic, K*mu).
        let k = 159.0e9;
        let poly = Polynomial::linear(k);
        let linear = LinearEos { bulk_modulus: k };
        for mu in [-0.05, -1e-6, 0.0, 1e-6, 0.01, 0.2] {
            let p = poly.evaluate(mu);
            let l = linear.evaluate(mu);
            assert_eq!(p.base, l.base, "mu = {mu}");
            assert_eq!(p.d_base_d_mu, l.d_base_d_mu, "mu = {mu}");
            assert_eq!(p.energy_coefficient, 0.0);
            assert_eq!(p.d_energy_coefficient_d_mu, 0.0);
        }
    }

    #[test]
    fn branches_follow_the_stated_polynomials() {
        // GOAL: compression and tension branches are the stated polynomials, linear in E.
        // SETUP: SAMPLE constants, E = 2 MJ/m^3, mu = 0.1 and -0.02.
        // REFERENCE: hand-expanded formulas; tolerance 1e-14 relative.
        let e = 2.0e6;
        let mu = 0.1;
        let expected = SAMPLE.a1 * mu
            + SAMPLE.a2 * mu * mu
            + SAMPLE.a3 * mu * mu * mu
            + (SAMPLE.b0 + SAMPLE.b1 * mu) * e;
        let got = SAMPLE.evaluate(mu).pressure(e);
        assert!(((got - expected) / expected).abs() < 1e-14);
        let mu = -0.02;
        let expected = SAMPLE.t1 * mu + SAMPLE.t2 * mu * mu + SAMPLE.b0 * e;
        let got = SAMPLE.evaluate(mu).pressure(e);
        assert!(((got - expected) / expected).abs() < 1e-14);
        // Continuous at mu = 0: both branches give B0 E.
        assert_eq!(SAMPLE.evaluate(0.0).pressure(e), SAMPLE.b0 * e);
        assert_eq!(SAMPLE.evaluate(-0.0).pressure(e), SAMPLE.b0 * e);
    }

    #[test]
    fn derivatives_match_central_differences() {
        // GOAL: d_base_d_mu and d_energy_coefficient_d_mu are the derivatives of the branches.
        // SETUP: SAMPLE, mu = 0.15 and -0.03, step 1e-6.
        // REFERENCE: central differences; tolerance 1e-7 relative.
        for mu in [0.15, -0.03] {
            let h = 1e-6;
            let terms = SAMPLE.evaluate(mu);
            let up = SAMPLE.evaluate(mu + h);
            let down = SAMPLE.evaluate(mu - h);
            let fd = (up.base - down.base) / (2.0 * h);
            assert!(((terms.d_base_d_mu - fd) / fd).abs() < 1e-7, "mu = {mu}");
            let fd_c = (up.energy_coefficient - down.energy_coefficient) / (2.0 * h);
            assert!(
                (terms.d_energy_coefficient_d_mu - fd_c).abs() < 1e-7,
                "mu = {mu}"
            );
        }
    }

    #[test]
    fn bad_constants_give_typed_errors() {
        // GOAL: validate() names the offending field.
        // SETUP: SAMPLE with one field broken at a time. REFERENCE: ParameterError variants.
        let mut p = SAMPLE;
        p.a1 = 0.0;
        assert_eq!(
            p.validate(),
            Err(ParameterError::NotPositive {
                field: "a1",
                value: 0.0
            })
        );
        let mut p = SAMPLE;
        p.t1 = -1.0;
        assert_eq!(
            p.validate(),
            Err(ParameterError::NotPositive {
                field: "t1",
                value: -1.0
            })
        );
        let mut p = SAMPLE;
        p.b1 = f64::NAN;
        assert_eq!(p.validate(), Err(ParameterError::NotFinite { field: "b1" }));
        assert_eq!(SAMPLE.validate(), Ok(()));
    }
}

crate::struct_constants!(
    Polynomial,
    [
        a1 = ("A1", "Pa", crate::parameters::FIXED),
        a2 = ("A2", "Pa", crate::parameters::FIXED),
        a3 = ("A3", "Pa", crate::parameters::FIXED),
        b0 = ("B0", "-", crate::parameters::FIXED),
        b1 = ("B1", "-", crate::parameters::FIXED),
        t1 = ("T1", "Pa", crate::parameters::FIXED),
        t2 = ("T2", "Pa", crate::parameters::FIXED),
    ]
);
