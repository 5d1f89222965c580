//! Khan-Huang-Liang model (Khan & Liang, Int. J. Plasticity 15 (1999) 1089-1109; Khan, Suh &
//! Kazmi, Int. J. Plasticity 20 (2004) 2233-2248): strain hardening that weakens with strain
//! rate, a power-law rate factor and Johnson-Cook's thermal factor,
//!
//! `sigma_y = [A + B (1 - ln(deps_p) / ln(D0p))^n1 eps_p^n0] (deps_p / e0)^C (1 - T*^m)`,
//!
//! with `D0p` an upper bound of the strain rates (1e6 /s in the papers; the rate in `ln` is in
//! 1/s), `e0` the reference rate and `T* = (T - Tr)/(Tm - Tr)` in [0, 1]. Unlike Johnson-Cook
//! the work hardening depends on the rate (the "coupled" term); the papers fitted it to
//! titanium alloys, tantalum and OFHC copper, whose hardening falls at high rates.
//!
//! Below [`KhanHuangLiang::MINIMUM_RATE`] the rate is held at that floor (the coupled factor
//! grows without bound as the rate falls, and `(rate/e0)^C` vanishes), so the zero-rate
//! (elastic-check) flow stress is finite and continuous; at and above `D0p` the coupled factor
//! is 0 (the model is defined below its upper rate). Along a return path the first derivative
//! is exact; the second and third are reported unbounded, as for Preston-Tonks-Wallace, so its
//! returns converge by safeguarded Newton steps alone.
//!
//! The coupled factor makes the flow stress fall with rate wherever `n1 B eps^n0 w^(n1 - 1) /
//! ((A + B w^n1 eps^n0) ln D0p) > C`: near `D0p` always (`w -> 0`), and at large strain when
//! `n1` is large against `C`. The implicit rate treatment's yield check uses the flow stress
//! at the rate floor, which assumes the flow stress grows with rate; a calibration enforces
//! that over its checked rates (`monotone_rate`), and constants that break it make loading
//! steps elastic where the dynamic flow stress is exceeded.

use super::hardening::power_term;
use super::{FlowStress, ThermalTerm};
use crate::error::{check, ParameterError};
use crate::math::{ln, pow};
use crate::parameters;

/// Khan-Huang-Liang constants (SI).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct KhanHuangLiang {
    /// Yield stress `A` (Pa).
    pub yield_stress: f64,
    /// Hardening modulus `B` (Pa).
    pub hardening_modulus: f64,
    /// Hardening exponent `n0` (-).
    pub hardening_exponent: f64,
    /// Rate-coupling exponent `n1` (-) of `(1 - ln(rate)/ln(D0p))`.
    pub coupling_exponent: f64,
    /// Rate exponent `C` (-).
    pub rate_sensitivity: f64,
    /// Reference rate `e0` (1/s) of the rate factor.
    pub reference_rate: f64,
    /// Upper bound of the strain rates `D0p` (1/s), 1e6 in the papers.
    pub upper_rate: f64,
    /// Thermal exponent `m` (-).
    pub thermal_exponent: f64,
    /// Reference temperature `Tr` (K).
    pub reference_temperature: f64,
    /// Melting temperature `Tm` (K).
    pub melting_temperature: f64,
}

impl KhanHuangLiang {
    /// Floor of the plastic strain rate (1/s): below it the flow stress is that at the floor.
    pub const MINIMUM_RATE: f64 = 1e-6;

    /// Illustrative constants in the range of Khan et al.'s (2004) titanium-alloy fits (A 1
    /// GPa, B 0.6 GPa, n0 0.4, n1 0.3, C 0.02, e0 1 /s, D0p 1e6 /s, m 0.8, Tr 298 K, Tm 1878
    /// K), chosen so that the flow stress grows with rate from the rate floor to 1e4 /s at
    /// plastic strains up to 1 (see the module documentation); not a published set: the C
    /// ABI's base and the checks' sample.
    pub const ILLUSTRATIVE: KhanHuangLiang = KhanHuangLiang {
        yield_stress: 1000.0e6,
        hardening_modulus: 600.0e6,
        hardening_exponent: 0.4,
        coupling_exponent: 0.3,
        rate_sensitivity: 0.02,
        reference_rate: 1.0,
        upper_rate: 1.0e6,
        thermal_exponent: 0.8,
        reference_temperature: 298.0,
        melting_temperature: 1878.0,
    };

    /// Johnson-Cook's thermal factor with this model's constants.
    #[inline]
    fn thermal(&self) -> ThermalTerm {
        ThermalTerm::HomologousPower {
            exponent: self.thermal_exponent,
            reference_temperature: self.reference_temperature,
            melting_temperature: self.melting_temperature,
        }
    }

    /// Johnson-Cook's `1 - T*^m` at `temperature`: temperature only, so the return mapping
    /// evaluates it once per step ([`super::Strength::at_temperature`]).
    #[inline]
    pub fn thermal_factor(&self, temperature: f64) -> f64 {
        self.thermal().evaluate(temperature)
    }

    /// Flow stress and its strain and rate derivatives at fixed temperature.
    #[inline]
    pub fn flow_stress(
        &self,
        plastic_strain: f64,
        plastic_strain_rate: f64,
        temperature: f64,
    ) -> FlowStress {
        let thermal = self.thermal_factor(temperature);
        self.flow_stress_with_thermal(plastic_strain, plastic_strain_rate, thermal)
    }

    /// [`Self::flow_stress`] with its thermal factor ([`Self::thermal_factor`]) already
    /// evaluated.
    #[inline]
    pub fn flow_stress_with_thermal(
        &self,
        plastic_strain: f64,
        plastic_strain_rate: f64,
        thermal: f64,
    ) -> FlowStress {
        let (rate, active) = super::floored_rate(plastic_strain_rate, Self::MINIMUM_RATE);
        let hardening = power_term(
            self.hardening_modulus,
            self.hardening_exponent,
            plastic_strain,
        );
        // The coupled factor w^n1, w = 1 - ln(rate)/ln(D0p), and its rate derivative.
        let log_upper = ln(self.upper_rate);
        let w = 1.0 - ln(rate) / log_upper;
        let (coupled, d_coupled) = if w > 0.0 {
            let value = pow(w, self.coupling_exponent);
            let slope = if active {
                -self.coupling_exponent * value / (w * rate * log_upper)
            } else {
                0.0
            };
            (value, slope)
        } else {
            (0.0, 0.0)
        };
        let factor = pow(rate / self.reference_rate, self.rate_sensitivity);
        let d_factor = if active {
            self.rate_sensitivity * factor / rate
        } else {
            0.0
        };
        let strain_part = self.yield_stress + hardening.value * coupled;
        FlowStress {
            value: strain_part * factor * thermal,
            d_plastic_strain: hardening.slope * coupled * factor * thermal,
            d_rate: (hardening.value * d_coupled * factor + strain_part * d_factor) * thermal,
        }
    }

    /// Reject non-physical constants: positive `A`, non-negative `B`, exponents and `C`,
    /// `D0p` above 1 /s (so that `ln(D0p) > 0`) and above the reference rate, `Tr < Tm`.
    pub fn validate(&self) -> Result<(), ParameterError> {
        check::positive("yield_stress", self.yield_stress)?;
        check::non_negative("hardening_modulus", self.hardening_modulus)?;
        check::range("hardening_exponent", self.hardening_exponent, 0.0, 2.0)?;
        check::range("coupling_exponent", self.coupling_exponent, 0.0, 5.0)?;
        check::range("rate_sensitivity", self.rate_sensitivity, 0.0, 1.0)?;
        check::positive("reference_rate", self.reference_rate)?;
        check::range("upper_rate", self.upper_rate, 1.0 + 1e-9, f64::MAX)?;
        check::range("upper_rate", self.upper_rate, self.reference_rate, f64::MAX)?;
        self.thermal().validate()
    }
}

// Search ranges: A, B as every stress; n0 as JC's n; n1 in [0, 3] and C in [0, 0.1] bracket
// the published fits (Khan & Liang 1999; Khan et al. 2004: n1 0.3-1.9, C 0.003-0.03); the
// reference and upper rates and the temperatures are fixed.
crate::struct_constants!(
    KhanHuangLiang,
    [
        yield_stress = ("A", "Pa", parameters::STRESS),
        hardening_modulus = ("B", "Pa", parameters::STRESS),
        hardening_exponent = ("n0", "-", parameters::HARDENING_EXPONENT),
        coupling_exponent = ("n1", "-", Some((0.0, 3.0))),
        rate_sensitivity = ("C", "-", Some((0.0, 0.1))),
        reference_rate = ("e0", "1/s", parameters::FIXED),
        upper_rate = ("D0p", "1/s", parameters::FIXED),
        thermal_exponent = ("m", "-", parameters::THERMAL_EXPONENT),
        reference_temperature = ("Tr", "K", parameters::FIXED),
        melting_temperature = ("Tm", "K", parameters::FIXED),
    ]
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_flow_stress_is_the_published_law_and_its_slopes_are_its_derivatives() {
        // GOAL: KHL as printed (Khan et al. 2004 eq. 1) and its strain and rate slopes.
        // SETUP: the illustrative constants at 298 and 800 K, rates 1e-3 to 1e5 /s, strains 0.01
        //        to 0.5. REFERENCE: the law evaluated with libm's functions; central
        //        differences (relative steps 1e-6) within 1e-6 of the derivative's scale.
        let m = KhanHuangLiang::ILLUSTRATIVE;
        m.validate().unwrap();
        for &t in &[298.0, 800.0] {
            for &rate in &[1e-3, 1.0, 1e3, 1e5] {
                for &eps in &[0.01, 0.1, 0.5] {
                    let star: f64 = ((t - 298.0_f64) / (1878.0 - 298.0)).clamp(0.0, 1.0);
                    let thermal = if star == 0.0 {
                        1.0
                    } else {
                        1.0 - libm::pow(star, 0.8)
                    };
                    let w = 1.0 - libm::log(rate) / libm::log(1e6);
                    let expected = (1000e6 + 600e6 * libm::pow(w, 0.3) * libm::pow(eps, 0.4))
                        * libm::pow(rate, 0.02)
                        * thermal;
                    let f = m.flow_stress(eps, rate, t);
                    assert!((f.value / expected - 1.0).abs() < 1e-14, "{f:?} {expected}");
                    let h = 1e-6 * eps;
                    let d_eps = (m.flow_stress(eps + h, rate, t).value
                        - m.flow_stress(eps - h, rate, t).value)
                        / (2.0 * h);
                    let k = 1e-6 * rate;
                    let d_rate = (m.flow_stress(eps, rate + k, t).value
                        - m.flow_stress(eps, rate - k, t).value)
                        / (2.0 * k);
                    assert!(
                        (f.d_plastic_strain / d_eps - 1.0).abs() < 1e-6,
                        "{t} {rate} {eps}"
                    );
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
    fn the_rate_floor_and_the_upper_rate_keep_the_flow_stress_finite() {
        // GOAL: finite flow stress at rest (the elastic check) and at the upper rate.
        // SETUP: rates 0, the floor, D0p and 10 D0p. REFERENCE: the value at rest equals the
        //        floor's with zero rate slope; at and above D0p the hardening is gone (A times
        //        the rate and thermal factors).
        let m = KhanHuangLiang::ILLUSTRATIVE;
        let rest = m.flow_stress(0.1, 0.0, 298.0);
        assert_eq!(
            rest.value,
            m.flow_stress(0.1, KhanHuangLiang::MINIMUM_RATE, 298.0)
                .value
        );
        assert_eq!(rest.d_rate, 0.0);
        for rate in [1e6, 1e7] {
            let f = m.flow_stress(0.1, rate, 298.0);
            let expected = 1000e6 * libm::pow(rate, 0.02);
            assert!((f.value / expected - 1.0).abs() < 1e-14, "{rate}: {f:?}");
        }
    }
}
