//! Flow-stress (strength) models: `sigma_y(eps_p, deps_p, T)` and its partial derivatives.
//!
//! A model is either a [`ComposedStrength`] — a product of a hardening term, a rate term and a
//! thermal term, each an enum, so that a missing term can be added without writing a new
//! model — or [`ZerilliArmstrong`], whose rate and temperature dependence are coupled.
//!
//! The named families of seed 000 (JC, ZA, MJC, TJC) are parameter structs with `validate()`
//! and their constants' descriptions ([`crate::parameters`]); each converts into a
//! [`Strength`].

mod composed;
mod hardening;
mod johnson_cook;
mod modified_johnson_cook;
mod rate;
mod thermal;
mod two_rate_johnson_cook;
mod zerilli_armstrong;

pub use composed::ComposedStrength;
pub use hardening::Hardening;
pub use johnson_cook::JohnsonCook;
pub use modified_johnson_cook::ModifiedJohnsonCook;
pub use rate::RateTerm;
pub use thermal::{homologous_temperature, ThermalTerm};
pub use two_rate_johnson_cook::TwoRateJohnsonCook;
pub use zerilli_armstrong::{CrystalStructure, ZerilliArmstrong};

use crate::error::ParameterError;

/// A flow stress and its partial derivatives at fixed temperature.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlowStress {
    /// `sigma_y` (Pa).
    pub value: f64,
    /// `d sigma_y / d eps_p` (Pa).
    pub d_plastic_strain: f64,
    /// `d sigma_y / d deps_p` (Pa s).
    pub d_rate: f64,
}

/// A strength model: the von Mises flow stress as a function of equivalent plastic strain,
/// plastic strain rate and temperature.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "kebab-case"))]
pub enum Strength {
    /// `hardening(eps_p) * rate(deps_p) * thermal(T)`.
    Composed(ComposedStrength),
    /// Zerilli-Armstrong (BCC or FCC): rate and temperature coupled.
    ZerilliArmstrong(ZerilliArmstrong),
}

impl Strength {
    /// Flow stress and its derivatives at plastic strain `plastic_strain`, plastic strain rate
    /// `plastic_strain_rate` (1/s) and temperature `temperature` (K).
    #[inline]
    pub fn flow_stress(
        &self,
        plastic_strain: f64,
        plastic_strain_rate: f64,
        temperature: f64,
    ) -> FlowStress {
        self.at_temperature(temperature)
            .flow_stress(plastic_strain, plastic_strain_rate)
    }

    /// The model at a fixed temperature, with its temperature-only factors (the thermal term
    /// `theta(T)` of a composed model) evaluated once: the return mapping holds `T_n` fixed
    /// while it iterates on the plastic multiplier.
    #[inline]
    pub fn at_temperature(&self, temperature: f64) -> FlowAtTemperature<'_> {
        let thermal = match self {
            Strength::Composed(model) => model.thermal.evaluate(temperature),
            Strength::ZerilliArmstrong(_) => 1.0,
        };
        FlowAtTemperature {
            strength: self,
            temperature,
            thermal,
        }
    }

    /// Reject non-physical parameters.
    pub fn validate(&self) -> Result<(), ParameterError> {
        match self {
            Strength::Composed(model) => model.validate(),
            Strength::ZerilliArmstrong(model) => model.validate(),
        }
    }
}

/// A [`Strength`] at a fixed temperature (see [`Strength::at_temperature`]). Bit-identical to
/// [`Strength::flow_stress`] at that temperature.
#[derive(Clone, Copy, Debug)]
pub struct FlowAtTemperature<'a> {
    strength: &'a Strength,
    temperature: f64,
    /// `theta(T)` of a composed model (1 for Zerilli-Armstrong, whose temperature dependence
    /// is coupled with the rate).
    thermal: f64,
}

impl FlowAtTemperature<'_> {
    /// Flow stress and its derivatives at plastic strain `plastic_strain` and plastic strain
    /// rate `plastic_strain_rate` (1/s).
    #[inline]
    pub fn flow_stress(&self, plastic_strain: f64, plastic_strain_rate: f64) -> FlowStress {
        match self.strength {
            Strength::Composed(model) => model.flow_stress_with_thermal(
                plastic_strain,
                plastic_strain_rate,
                self.temperature,
                self.thermal,
            ),
            Strength::ZerilliArmstrong(model) => {
                model.flow_stress(plastic_strain, plastic_strain_rate, self.temperature)
            }
        }
    }
}

impl From<ComposedStrength> for Strength {
    fn from(model: ComposedStrength) -> Self {
        Strength::Composed(model)
    }
}

impl From<ZerilliArmstrong> for Strength {
    fn from(model: ZerilliArmstrong) -> Self {
        Strength::ZerilliArmstrong(model)
    }
}
