//! A flow stress composed of independent terms: `sigma_y = h(eps_p) r(deps_p) theta(T)`.

use super::{FlowStress, Hardening, RateTerm, ThermalTerm};
use crate::error::ParameterError;

/// `sigma_y = hardening(eps_p) * rate(deps_p) * thermal(T)`. JC, MJC and TJC are instances;
/// the diagnosis adds a physics term by swapping one of the three enums.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct ComposedStrength {
    /// Strain-hardening term.
    pub hardening: Hardening,
    /// Strain-rate factor.
    pub rate: RateTerm,
    /// Thermal-softening factor.
    pub thermal: ThermalTerm,
}

impl ComposedStrength {
    /// Flow stress and its strain and rate derivatives at fixed temperature.
    #[inline]
    pub fn flow_stress(
        &self,
        plastic_strain: f64,
        plastic_strain_rate: f64,
        temperature: f64,
    ) -> FlowStress {
        self.flow_stress_with_thermal(
            plastic_strain,
            plastic_strain_rate,
            temperature,
            self.thermal.evaluate(temperature),
        )
    }

    /// [`Self::flow_stress`] with the thermal factor `theta = thermal(temperature)` given.
    #[inline]
    pub fn flow_stress_with_thermal(
        &self,
        plastic_strain: f64,
        plastic_strain_rate: f64,
        temperature: f64,
        theta: f64,
    ) -> FlowStress {
        let (h, dh) = self.hardening.evaluate(plastic_strain);
        let (r, dr) = self.rate.evaluate(plastic_strain_rate, temperature);
        FlowStress {
            value: h * r * theta,
            d_plastic_strain: dh * r * theta,
            d_rate: h * dr * theta,
        }
    }

    /// Validate every term.
    pub fn validate(&self) -> Result<(), ParameterError> {
        self.hardening.validate()?;
        self.rate.validate()?;
        self.thermal.validate()
    }
}
