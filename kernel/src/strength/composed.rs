//! A flow stress composed of independent terms: `sigma_y = h(eps_p) r(deps_p) theta(T)`.

use super::{FlowStress, Hardening, PathFlow, RateTerm, ThermalTerm};
use crate::error::ParameterError;
use crate::math::lanes::{Calls, Direct, Transcendentals};
use crate::parameters::{Constants, Parameter};

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
        let h = self.hardening.evaluate(plastic_strain);
        let r = self.rate.evaluate(plastic_strain_rate, temperature);
        FlowStress {
            value: h.value * r.value * theta,
            d_plastic_strain: h.slope * r.value * theta,
            d_rate: h.value * r.slope * theta,
        }
    }

    /// The flow stress along a return path, `h(eps_n + dl) r(dl/dt) theta`, and its first
    /// three derivatives in `dl` (see [`PathFlow`]), with `theta = thermal(temperature)`
    /// given and the step's `inverse_dt = 1/dt`.
    #[inline]
    pub fn along_path_with_thermal(
        &self,
        plastic_strain: f64,
        dl: f64,
        inverse_dt: f64,
        temperature: f64,
        theta: f64,
    ) -> PathFlow {
        self.along_path_with(
            plastic_strain,
            dl,
            inverse_dt,
            temperature,
            theta,
            &mut Direct,
        )
    }

    /// [`Self::along_path_with_thermal`] with its transcendental functions from `math`.
    #[inline(always)]
    pub fn along_path_with(
        &self,
        plastic_strain: f64,
        dl: f64,
        inverse_dt: f64,
        temperature: f64,
        theta: f64,
        math: &mut impl Transcendentals,
    ) -> PathFlow {
        let h = self.hardening.evaluate_with(plastic_strain + dl, math);
        let r = self
            .rate
            .evaluate_with(dl * inverse_dt, temperature, math)
            .along_rate(inverse_dt);
        h.product(&r).scaled(theta).path_flow(self.rate.kink_rate())
    }

    /// Announce the calls [`Self::along_path_with`] makes (see [`Calls`]).
    #[inline(always)]
    pub fn announce_path(&self, plastic_strain: f64, dl: f64, inverse_dt: f64, calls: &mut Calls) {
        self.hardening.announce(plastic_strain + dl, calls);
        self.rate.announce(dl * inverse_dt, calls);
    }

    /// The names of the three terms, as they prefix their constants' paths.
    pub const TERMS: [&'static str; 3] = ["hardening", "rate", "thermal"];

    /// The term named `term` (one of [`Self::TERMS`]).
    fn term_mut(&mut self, term: &str) -> Option<&mut dyn Constants> {
        match term {
            "hardening" => Some(&mut self.hardening),
            "rate" => Some(&mut self.rate),
            "thermal" => Some(&mut self.thermal),
            _ => None,
        }
    }

    /// The constants of every term, with the term's name: the constant `name` of term `term`
    /// has the path `term.name` (e.g. `rate.rate_sensitivity`).
    pub fn parameters(&self) -> impl Iterator<Item = (&'static str, &'static Parameter)> {
        let hardening = self.hardening.parameters().iter().map(|p| ("hardening", p));
        let rate = self.rate.parameters().iter().map(|p| ("rate", p));
        let thermal = self.thermal.parameters().iter().map(|p| ("thermal", p));
        hardening.chain(rate).chain(thermal)
    }

    /// Validate every term.
    pub fn validate(&self) -> Result<(), ParameterError> {
        self.hardening.validate()?;
        self.rate.validate()?;
        self.thermal.validate()
    }
}

impl crate::parameters::ConstantPaths for ComposedStrength {
    /// `path`: `term.name` (`hardening`, `rate` or `thermal`).
    fn slot(&mut self, path: &str) -> Option<&mut f64> {
        let (term, name) = path.split_once('.')?;
        self.term_mut(term)?.named_slot(name)
    }
}
