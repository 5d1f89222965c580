//! Thermal-softening terms `theta(T)`.

use crate::error::{check, ParameterError};
use crate::math::pow;
use crate::parameters;

/// Homologous temperature `T* = (T - Tr)/(Tm - Tr)` clamped to `[0, 1]`.
#[inline]
pub fn homologous_temperature(
    temperature: f64,
    reference_temperature: f64,
    melting_temperature: f64,
) -> f64 {
    let ratio =
        (temperature - reference_temperature) / (melting_temperature - reference_temperature);
    crate::math::clamp(ratio, 0.0, 1.0)
}

/// Multiplicative thermal-softening factor on the flow stress.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "kebab-case"))]
pub enum ThermalTerm {
    /// No thermal softening: `theta = 1`.
    None,
    /// Johnson-Cook: `1 - T*^m`.
    HomologousPower {
        /// Exponent `m` (-).
        exponent: f64,
        /// Reference (room) temperature `Tr` (K).
        reference_temperature: f64,
        /// Melting temperature `Tm` (K).
        melting_temperature: f64,
    },
    /// Linear in homologous temperature: `1 - T*`.
    Linear {
        /// Reference temperature `Tr` (K).
        reference_temperature: f64,
        /// Melting temperature `Tm` (K).
        melting_temperature: f64,
    },
}

impl ThermalTerm {
    /// `theta(T)`.
    #[inline]
    pub fn evaluate(&self, temperature: f64) -> f64 {
        match *self {
            ThermalTerm::None => 1.0,
            ThermalTerm::HomologousPower {
                exponent,
                reference_temperature,
                melting_temperature,
            } => {
                let t_star =
                    homologous_temperature(temperature, reference_temperature, melting_temperature);
                if t_star == 0.0 {
                    1.0
                } else {
                    1.0 - pow(t_star, exponent)
                }
            }
            ThermalTerm::Linear {
                reference_temperature,
                melting_temperature,
            } => {
                1.0 - homologous_temperature(
                    temperature,
                    reference_temperature,
                    melting_temperature,
                )
            }
        }
    }

    /// Reject non-physical constants: `m > 0`, `0 < Tr < Tm`.
    pub fn validate(&self) -> Result<(), ParameterError> {
        let (reference_temperature, melting_temperature) = match *self {
            ThermalTerm::None => return Ok(()),
            ThermalTerm::HomologousPower {
                exponent,
                reference_temperature,
                melting_temperature,
            } => {
                check::range("thermal_exponent", exponent, 1e-3, 10.0)?;
                (reference_temperature, melting_temperature)
            }
            ThermalTerm::Linear {
                reference_temperature,
                melting_temperature,
            } => (reference_temperature, melting_temperature),
        };
        check::positive("reference_temperature", reference_temperature)?;
        check::positive("melting_temperature", melting_temperature)?;
        if melting_temperature <= reference_temperature {
            return Err(ParameterError::Inconsistent {
                field: "melting_temperature",
                other: "reference_temperature",
            });
        }
        Ok(())
    }
}

crate::enum_constants!(ThermalTerm, {
    None {},
    HomologousPower {
        exponent = ("m", "-", parameters::THERMAL_EXPONENT),
        reference_temperature = ("Tr", "K", parameters::FIXED),
        melting_temperature = ("Tm", "K", parameters::FIXED),
    },
    Linear {
        reference_temperature = ("Tr", "K", parameters::FIXED),
        melting_temperature = ("Tm", "K", parameters::FIXED),
    },
});
