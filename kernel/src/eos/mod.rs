//! Equations of state: pressure from compression `mu = rho/rho0 - 1` and internal energy `E`
//! per unit *reference* volume (J/m^3, the LS-DYNA convention).
//!
//! Every EoS is written in energy-linear form at fixed compression,
//! `p(mu, E) = base(mu) + energy_coefficient(mu) * E`, which lets the stress update solve the
//! energy equation `E1 = E0 + W_dev - (p0 + p1)/2 (V1 - V0)` in closed form (no iteration),
//! exactly as explicit hydrocodes do.

mod linear;

pub use linear::LinearEos;

use crate::error::ParameterError;

/// Pressure at fixed compression in energy-linear form, with derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyLinearPressure {
    /// `base(mu)` (Pa).
    pub base: f64,
    /// `d base / d mu` (Pa).
    pub d_base_d_mu: f64,
    /// `dp/dE` at fixed `mu` (-).
    pub energy_coefficient: f64,
    /// `d energy_coefficient / d mu` (-).
    pub d_energy_coefficient_d_mu: f64,
}

impl EnergyLinearPressure {
    /// `p = base + coefficient * E`.
    #[inline]
    pub fn pressure(&self, energy: f64) -> f64 {
        self.base + self.energy_coefficient * energy
    }

    /// `dp/dmu` at fixed `E`.
    #[inline]
    pub fn d_pressure_d_mu(&self, energy: f64) -> f64 {
        self.d_base_d_mu + self.d_energy_coefficient_d_mu * energy
    }
}

/// An equation of state.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Eos {
    /// `p = K mu`.
    Linear(LinearEos),
}

impl Eos {
    /// Pressure terms at compression `mu`. `history` is the EoS internal variable carried in
    /// [`crate::MaterialState::eos_history`] (unused by history-free EoS); the returned
    /// second value is its updated value.
    #[inline]
    pub fn evaluate(&self, mu: f64, history: f64) -> (EnergyLinearPressure, f64) {
        match self {
            Eos::Linear(eos) => (eos.evaluate(mu), history),
        }
    }

    /// Initial value of the EoS history variable.
    pub fn initial_history(&self) -> f64 {
        0.0
    }

    /// Reject non-physical constants.
    pub fn validate(&self) -> Result<(), ParameterError> {
        match self {
            Eos::Linear(eos) => eos.validate(),
        }
    }

    /// Isentropic bulk sound speed squared `c^2 = dp/drho|_s` (m^2/s^2) at compression `mu`,
    /// energy `energy` (J/m^3 of reference volume), pressure `pressure`, reference density
    /// `reference_density`. With `dE = p rho0 drho / rho^2` along an isentrope,
    /// `c^2 = (dp/dmu)/rho0 + (dp/dE) p rho0 / rho^2`.
    pub fn sound_speed_squared(
        terms: &EnergyLinearPressure,
        mu: f64,
        energy: f64,
        pressure: f64,
        reference_density: f64,
    ) -> f64 {
        let density = reference_density * (1.0 + mu);
        terms.d_pressure_d_mu(energy) / reference_density
            + terms.energy_coefficient * pressure * reference_density / (density * density)
    }
}

impl From<LinearEos> for Eos {
    fn from(eos: LinearEos) -> Self {
        Eos::Linear(eos)
    }
}
