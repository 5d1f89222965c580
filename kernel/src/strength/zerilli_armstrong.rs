//! Zerilli-Armstrong dislocation-mechanics model (Zerilli & Armstrong 1987), as in seed 000:
//!
//! - BCC: `sigma_y = sigma_a + C1 exp(-C3 T + C4 T ln e*) + C5 eps_p^n`
//! - FCC: `sigma_y = sigma_a + C2 eps_p^(1/2) exp(-C3 T + C4 T ln e*)`
//!
//! with `e* = deps_p / e0`, `e0 = 1 /s`. Temperature enters as absolute `T` (K), coupled with
//! rate, so this model is not a product of independent terms. Below
//! [`ZerilliArmstrong::MINIMUM_RATE_RATIO`] the rate ratio is held at that floor, so the
//! zero-rate (elastic-check) flow stress is finite and continuous.

use super::hardening::{announce_power_term, power_term_with};
use super::{FlowStress, PathFlow, TermValue};
use crate::error::{check, ParameterError};
use crate::math::lanes::{Calls, Direct, Function, Transcendentals};
use crate::math::sqrt;
use crate::parameters;

/// Lattice structure selecting the ZA form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum CrystalStructure {
    /// Body-centred cubic (steels): thermal part independent of strain.
    Bcc,
    /// Face-centred cubic (copper, austenite): thermal part scales with `eps_p^(1/2)`.
    Fcc,
}

/// Zerilli-Armstrong constants (SI).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct ZerilliArmstrong {
    /// BCC or FCC form.
    pub structure: CrystalStructure,
    /// Athermal stress `sigma_a` including Hall-Petch `k d^-1/2` (Pa).
    pub athermal_stress: f64,
    /// `C1` (Pa), BCC thermal-activation stress. 0 when absent from a file: the other form does not use it.
    #[cfg_attr(feature = "serde", serde(default))]
    pub c1: f64,
    /// `C2` (Pa), FCC thermal-activation stress. 0 when absent from a file: the other form does not use it.
    #[cfg_attr(feature = "serde", serde(default))]
    pub c2: f64,
    /// `C3` (1/K).
    pub c3: f64,
    /// `C4` (1/K).
    pub c4: f64,
    /// `C5` (Pa), BCC strain-hardening modulus. 0 when absent from a file: the other form does not use it.
    #[cfg_attr(feature = "serde", serde(default))]
    pub c5: f64,
    /// `n` (-), BCC strain-hardening exponent. 0 when absent from a file: the other form does not use it.
    #[cfg_attr(feature = "serde", serde(default))]
    pub exponent: f64,
    /// Reference rate `e0` (1/s).
    pub reference_rate: f64,
}

impl ZerilliArmstrong {
    /// Zerilli & Armstrong (1987) BCC constants for Armco iron: C1 1033 MPa, C3 0.00698 /K,
    /// C4 0.000415 /K, C5 266 MPa, n 0.289, e0 1 /s; the athermal stress (grain-size term) is
    /// not in their fit and is set to 65 MPa here, a typical Hall-Petch contribution.
    pub const ARMCO_IRON: ZerilliArmstrong = ZerilliArmstrong {
        structure: CrystalStructure::Bcc,
        athermal_stress: 65.0e6,
        c1: 1033.0e6,
        c2: 0.0,
        c3: 0.00698,
        c4: 0.000415,
        c5: 266.0e6,
        exponent: 0.289,
        reference_rate: 1.0,
    };

    /// Floor of `e* = deps_p / e0` inside `ln` (quasi-static limit).
    pub const MINIMUM_RATE_RATIO: f64 = 1e-6;

    /// The thermal-activation factor `exp(-C3 T + C4 T ln e*)` = `exp(-C3 T) e*^k`, `k = C4 T`,
    /// and its first three derivatives in the rate (each brings a factor `(k - j)/rate`);
    /// constant below the rate floor.
    #[inline]
    fn activation(
        &self,
        plastic_strain_rate: f64,
        temperature: f64,
        math: &mut impl Transcendentals,
    ) -> TermValue {
        let raw_ratio = plastic_strain_rate / self.reference_rate;
        let ratio = Self::floored(raw_ratio);
        let log = math.ln(ratio);
        let (offset, k) = self.activation_exponent(temperature);
        let value = math.exp(offset + k * log);
        if raw_ratio > Self::MINIMUM_RATE_RATIO {
            let slope = value * k / plastic_strain_rate;
            let curvature = slope * (k - 1.0) / plastic_strain_rate;
            TermValue {
                value,
                slope,
                curvature,
                third: curvature * (k - 2.0) / plastic_strain_rate,
            }
        } else {
            TermValue {
                value,
                ..TermValue::CONSTANT_ZERO
            }
        }
    }

    /// The activation's exponent `-C3 T + k ln e*` as its offset `-C3 T` and slope `k = C4 T`
    /// (the formula and its announcement form the exponent from these, bit for bit alike).
    #[inline(always)]
    fn activation_exponent(&self, temperature: f64) -> (f64, f64) {
        (-self.c3 * temperature, self.c4 * temperature)
    }

    /// The rate ratio `e*` as `ln` takes it: `raw_ratio`, held at
    /// [`Self::MINIMUM_RATE_RATIO`] below it.
    #[inline(always)]
    fn floored(raw_ratio: f64) -> f64 {
        if raw_ratio > Self::MINIMUM_RATE_RATIO {
            raw_ratio
        } else {
            Self::MINIMUM_RATE_RATIO
        }
    }

    /// The strain term and its first three derivatives: `C5 eps^n` (BCC) or `C2 eps^(1/2)`
    /// (FCC, with `sqrt`), `eps` clamped at 0.
    #[inline]
    fn hardening(&self, plastic_strain: f64, math: &mut impl Transcendentals) -> TermValue {
        let eps = if plastic_strain > 0.0 {
            plastic_strain
        } else {
            0.0
        };
        match self.structure {
            CrystalStructure::Bcc => power_term_with(self.c5, self.exponent, eps, math),
            CrystalStructure::Fcc => {
                if self.c2 == 0.0 {
                    TermValue::CONSTANT_ZERO
                } else if eps == 0.0 {
                    TermValue {
                        value: 0.0,
                        slope: f64::INFINITY,
                        curvature: f64::INFINITY,
                        third: f64::INFINITY,
                    }
                } else {
                    let root = sqrt(eps);
                    let slope = 0.5 * self.c2 / root;
                    let curvature = -0.5 * slope / eps;
                    TermValue {
                        value: self.c2 * root,
                        slope,
                        curvature,
                        third: -1.5 * curvature / eps,
                    }
                }
            }
        }
    }

    /// The flow stress from its activation factor `activation` and strain term `hardening`
    /// (both as functions of one variable): BCC `sigma_a + C1 a + h`, FCC `sigma_a + h a`.
    #[inline]
    fn combine(&self, activation: TermValue, hardening: TermValue) -> TermValue {
        match self.structure {
            CrystalStructure::Bcc => activation
                .scaled(self.c1)
                .plus(self.athermal_stress)
                .sum(&hardening),
            CrystalStructure::Fcc => hardening.product(&activation).plus(self.athermal_stress),
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
        let activation = self.activation(plastic_strain_rate, temperature, &mut Direct);
        let hardening = self.hardening(plastic_strain, &mut Direct);
        let (d_plastic_strain, d_rate) = match self.structure {
            CrystalStructure::Bcc => (hardening.slope, self.c1 * activation.slope),
            CrystalStructure::Fcc => (
                hardening.slope * activation.value,
                hardening.value * activation.slope,
            ),
        };
        FlowStress {
            value: self.combine(activation, hardening).value,
            d_plastic_strain,
            d_rate,
        }
    }

    /// The flow stress along a return path, `sigma_y(eps_n + dl, dl/dt, T)`, and its first
    /// three derivatives in `dl` (see [`PathFlow`]), with the step's `inverse_dt = 1/dt`; the
    /// rate floor is its kink.
    #[inline]
    pub fn along_path(
        &self,
        plastic_strain: f64,
        dl: f64,
        inverse_dt: f64,
        temperature: f64,
    ) -> PathFlow {
        self.along_path_with(plastic_strain, dl, inverse_dt, temperature, &mut Direct)
    }

    /// [`Self::along_path`] with its `ln`, `exp` and `pow` from `math`.
    #[inline(always)]
    pub fn along_path_with(
        &self,
        plastic_strain: f64,
        dl: f64,
        inverse_dt: f64,
        temperature: f64,
        math: &mut impl Transcendentals,
    ) -> PathFlow {
        let activation = self
            .activation(dl * inverse_dt, temperature, math)
            .along_rate(inverse_dt);
        let hardening = self.hardening(plastic_strain + dl, math);
        self.combine(activation, hardening)
            .path_flow(Self::MINIMUM_RATE_RATIO * self.reference_rate)
    }

    /// Announce the calls [`Self::along_path_with`] makes (see [`Calls`]): the activation's
    /// `ln e*` and the `exp` of `-C3 T + C4 T ln e*` chained to it, then the BCC strain
    /// term's `pow(eps, n)` (the FCC term takes a square root).
    #[inline(always)]
    pub fn announce_path(
        &self,
        plastic_strain: f64,
        dl: f64,
        inverse_dt: f64,
        temperature: f64,
        calls: &mut Calls,
    ) {
        let ratio = Self::floored(dl * inverse_dt / self.reference_rate);
        if let Some(log) = calls.push(Function::Ln, ratio, 1.0) {
            let (offset, slope) = self.activation_exponent(temperature);
            calls.push_exp_of_affine(log, offset, slope);
        }
        if self.structure == CrystalStructure::Bcc {
            announce_power_term(self.exponent, plastic_strain + dl, calls);
        }
    }

    /// Reject non-physical constants: stresses and C3, C4 non-negative, positive yield.
    pub fn validate(&self) -> Result<(), ParameterError> {
        check::non_negative("athermal_stress", self.athermal_stress)?;
        check::non_negative("c1", self.c1)?;
        check::non_negative("c2", self.c2)?;
        check::non_negative("c3", self.c3)?;
        check::non_negative("c4", self.c4)?;
        check::non_negative("c5", self.c5)?;
        check::range("exponent", self.exponent, 0.0, 2.0)?;
        check::positive("reference_rate", self.reference_rate)?;
        let initial = match self.structure {
            CrystalStructure::Bcc => self.athermal_stress + self.c1,
            CrystalStructure::Fcc => self.athermal_stress,
        };
        if initial <= 0.0 && self.structure == CrystalStructure::Bcc {
            return Err(ParameterError::NotPositive {
                field: "athermal_stress",
                value: initial,
            });
        }
        if self.structure == CrystalStructure::Fcc && self.athermal_stress <= 0.0 {
            return Err(ParameterError::NotPositive {
                field: "athermal_stress",
                value: self.athermal_stress,
            });
        }
        Ok(())
    }
}

// Search ranges: seed 000 section 4.1 (BCC). The extracted text lost the exponents of C3 and
// C4; stoss uses [0, 1e-2] /K and [0, 1e-3] /K, which bracket published BCC steel values
// (e.g. Zerilli-Armstrong 1987 Armco iron: C3 = 0.00698 /K, C4 = 0.000415 /K). C2 (FCC) has
// no published range; stoss uses that of C1.
crate::struct_constants!(
    ZerilliArmstrong,
    [
        athermal_stress = ("sigma_a", "Pa", parameters::STRESS),
        c1 = ("C1", "Pa", Some((0.5e9, 3.0e9))),
        c2 = ("C2", "Pa", Some((0.5e9, 3.0e9))),
        c3 = ("C3", "1/K", Some((0.0, 1.0e-2))),
        c4 = ("C4", "1/K", Some((0.0, 1.0e-3))),
        c5 = ("C5", "Pa", parameters::STRESS),
        exponent = ("n", "-", Some((0.01, 1.5))),
        reference_rate = ("e0", "1/s", parameters::FIXED),
    ]
);
