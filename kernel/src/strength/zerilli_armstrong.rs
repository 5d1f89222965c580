//! Zerilli-Armstrong dislocation-mechanics model (Zerilli & Armstrong 1987), as in seed 000:
//!
//! - BCC: `sigma_y = sigma_a + C1 exp(-C3 T + C4 T ln e*) + C5 eps_p^n`
//! - FCC: `sigma_y = sigma_a + C2 eps_p^(1/2) exp(-C3 T + C4 T ln e*)`
//!
//! with `e* = deps_p / e0`, `e0 = 1 /s`. Temperature enters as absolute `T` (K), coupled with
//! rate, so this model is not a product of independent terms. Below
//! [`ZerilliArmstrong::MINIMUM_RATE_RATIO`] the rate ratio is held at that floor, so the
//! zero-rate (elastic-check) flow stress is finite and continuous.

use super::hardening::power_term;
use super::{FlowStress, PathFlow, TermValue};
use crate::error::{check, ParameterError};
use crate::math::{exp, ln, pow, sqrt};
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
    /// `C1` (Pa), BCC thermal-activation stress.
    pub c1: f64,
    /// `C2` (Pa), FCC thermal-activation stress.
    pub c2: f64,
    /// `C3` (1/K).
    pub c3: f64,
    /// `C4` (1/K).
    pub c4: f64,
    /// `C5` (Pa), BCC strain-hardening modulus.
    pub c5: f64,
    /// `n` (-), BCC strain-hardening exponent.
    pub exponent: f64,
    /// Reference rate `e0` (1/s).
    pub reference_rate: f64,
}

impl ZerilliArmstrong {
    /// Floor of `e* = deps_p / e0` inside `ln` (quasi-static limit).
    pub const MINIMUM_RATE_RATIO: f64 = 1e-6;

    /// Flow stress and its strain and rate derivatives at fixed temperature.
    #[inline]
    pub fn flow_stress(
        &self,
        plastic_strain: f64,
        plastic_strain_rate: f64,
        temperature: f64,
    ) -> FlowStress {
        let raw_ratio = plastic_strain_rate / self.reference_rate;
        let (ratio, ratio_active) = if raw_ratio > Self::MINIMUM_RATE_RATIO {
            (raw_ratio, true)
        } else {
            (Self::MINIMUM_RATE_RATIO, false)
        };
        let activation = exp(-self.c3 * temperature + self.c4 * temperature * ln(ratio));
        // d activation / d rate = activation * C4 T / rate (zero on the floor).
        let d_activation = if ratio_active {
            activation * self.c4 * temperature / plastic_strain_rate
        } else {
            0.0
        };
        let eps = if plastic_strain > 0.0 {
            plastic_strain
        } else {
            0.0
        };
        match self.structure {
            CrystalStructure::Bcc => {
                let (hardening, slope) = if self.c5 == 0.0 {
                    (0.0, 0.0)
                } else if eps == 0.0 {
                    (
                        0.0,
                        if self.exponent < 1.0 {
                            f64::INFINITY
                        } else {
                            0.0
                        },
                    )
                } else {
                    let powered = pow(eps, self.exponent);
                    (self.c5 * powered, self.c5 * self.exponent * powered / eps)
                };
                FlowStress {
                    value: self.athermal_stress + self.c1 * activation + hardening,
                    d_plastic_strain: slope,
                    d_rate: self.c1 * d_activation,
                }
            }
            CrystalStructure::Fcc => {
                let root = sqrt(eps);
                let slope = if eps == 0.0 {
                    f64::INFINITY
                } else {
                    0.5 * self.c2 * activation / root
                };
                FlowStress {
                    value: self.athermal_stress + self.c2 * root * activation,
                    d_plastic_strain: if self.c2 == 0.0 { 0.0 } else { slope },
                    d_rate: self.c2 * root * d_activation,
                }
            }
        }
    }

    /// The flow stress along a return path, `sigma_y(eps_n + dl, dl/dt, T)`, and its first
    /// three derivatives in `dl` (see [`PathFlow`]). The thermal-activation factor is
    /// `exp(-C3 T) (rate/e0)^k` with `k = C4 T`, each rate derivative bringing a factor
    /// `(k - j)/rate`; it is constant below the rate floor, whose rate is the kink.
    #[inline]
    pub fn along_path(&self, plastic_strain: f64, dl: f64, dt: f64, temperature: f64) -> PathFlow {
        let rate = dl / dt;
        let raw_ratio = rate / self.reference_rate;
        let ratio = if raw_ratio > Self::MINIMUM_RATE_RATIO {
            raw_ratio
        } else {
            Self::MINIMUM_RATE_RATIO
        };
        let value = exp(-self.c3 * temperature + self.c4 * temperature * ln(ratio));
        let activation = if raw_ratio > Self::MINIMUM_RATE_RATIO {
            let k = self.c4 * temperature;
            let slope = value * k / rate;
            let curvature = slope * (k - 1.0) / rate;
            TermValue {
                value,
                slope,
                curvature,
                third: curvature * (k - 2.0) / rate,
            }
        } else {
            TermValue {
                value,
                ..TermValue::CONSTANT_ZERO
            }
        }
        .along_rate(1.0 / dt);
        let eps = plastic_strain + dl;
        let eps = if eps > 0.0 { eps } else { 0.0 };
        let path = match self.structure {
            CrystalStructure::Bcc => activation
                .scaled(self.c1)
                .plus(self.athermal_stress)
                .sum(&power_term(self.c5, self.exponent, eps)),
            CrystalStructure::Fcc => {
                // C2 eps^(1/2) with sqrt, as in `flow_stress`.
                let root = sqrt(eps);
                let hardening = if self.c2 == 0.0 {
                    TermValue::CONSTANT_ZERO
                } else if eps == 0.0 {
                    TermValue {
                        value: 0.0,
                        slope: f64::INFINITY,
                        curvature: f64::INFINITY,
                        third: f64::INFINITY,
                    }
                } else {
                    let slope = 0.5 * self.c2 / root;
                    let curvature = -0.5 * slope / eps;
                    TermValue {
                        value: self.c2 * root,
                        slope,
                        curvature,
                        third: -1.5 * curvature / eps,
                    }
                };
                hardening.product(&activation).plus(self.athermal_stress)
            }
        };
        path.path_flow(Self::MINIMUM_RATE_RATIO * self.reference_rate)
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
