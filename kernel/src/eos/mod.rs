//! Equations of state: pressure from compression `mu = rho/rho0 - 1` and internal energy `E`
//! per unit *reference* volume (J/m^3, the LS-DYNA convention).
//!
//! Every EoS is written in energy-linear form at fixed compression,
//! `p(mu, E) = base(mu) + energy_coefficient(mu) * E`, which lets the stress update solve the
//! energy equation `E1 = E0 + W_dev - (p0 + p1)/2 (V1 - V0)` in closed form (no iteration),
//! exactly as explicit hydrocodes do.

mod jwl;
mod linear;
mod mie_gruneisen;
pub(crate) mod p_alpha;
mod polynomial;
mod tabulated_compaction;

pub use jwl::{ChapmanJouguet, Jwl};
pub use linear::LinearEos;
pub use mie_gruneisen::MieGruneisen;
pub use p_alpha::{PAlpha, MAX_DISTENSION_ITERATIONS};
pub use polynomial::Polynomial;
pub use tabulated_compaction::{CompactionPoint, TabulatedCompaction, MAX_COMPACTION_POINTS};

use crate::error::ParameterError;
use crate::parameters::{Constants, Parameter};

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
///
/// History-dependent variants keep their internal variable in
/// [`crate::MaterialState::eos_history`]: the maximum volumetric strain for
/// [`Eos::TabulatedCompaction`], the distension `alpha` for [`Eos::PAlpha`]. For those, the
/// derivatives in [`EnergyLinearPressure`] are taken at the updated (frozen) history, i.e. they
/// are the elastic unloading stiffness, which is what the bulk sound speed needs.
// The tabulated curve is a fixed array (no heap in the kernel), so that variant is larger
// than the others; boxing it is not an option.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "kebab-case"))]
pub enum Eos {
    /// `p = K mu`.
    Linear(LinearEos),
    /// Mie-Grüneisen, LS-DYNA `*EOS_GRUNEISEN` form.
    MieGruneisen(MieGruneisen),
    /// Polynomial (Autodyn; LS-DYNA `*EOS_LINEAR_POLYNOMIAL`-like), seed 001 eq. 4.10.
    Polynomial(Polynomial),
    /// Jones-Wilkins-Lee detonation products, LS-DYNA `*EOS_JWL`.
    Jwl(Jwl),
    /// Tabulated compaction, LS-DYNA `*EOS_TABULATED_COMPACTION` (no energy term).
    TabulatedCompaction(TabulatedCompaction),
    /// P-alpha porous compaction (Herrmann 1969) over a polynomial matrix, seed 001 eq. 4.11.
    PAlpha(PAlpha),
}

impl Eos {
    /// Pressure terms at compression `mu`. `history` is the EoS internal variable carried in
    /// [`crate::MaterialState::eos_history`] (unused by history-free EoS); the returned
    /// second value is its updated value.
    #[inline]
    pub fn evaluate(&self, mu: f64, history: f64) -> (EnergyLinearPressure, f64) {
        match self {
            Eos::Linear(eos) => (eos.evaluate(mu), history),
            Eos::MieGruneisen(eos) => (eos.evaluate(mu), history),
            Eos::Polynomial(eos) => (eos.evaluate(mu), history),
            Eos::Jwl(eos) => (eos.evaluate(mu), history),
            Eos::TabulatedCompaction(eos) => eos.evaluate(mu, history),
            Eos::PAlpha(eos) => eos.evaluate(mu, history),
        }
    }

    /// Initial value of the EoS history variable: `alpha0` for P-alpha, 0 otherwise (for the
    /// tabulated compaction EoS, the maximum volumetric strain of the undeformed state).
    pub fn initial_history(&self) -> f64 {
        match self {
            Eos::PAlpha(eos) => eos.initial_distension,
            _ => 0.0,
        }
    }

    /// The constants of this EoS (P-alpha: its own; its matrix's are `solid.<name>`); none
    /// for the tabulated compaction EoS, whose table is not a set of named constants.
    pub fn constants(&self) -> &'static [Parameter] {
        match self {
            Eos::Linear(eos) => eos.parameters(),
            Eos::MieGruneisen(eos) => eos.parameters(),
            Eos::Polynomial(eos) => eos.parameters(),
            Eos::Jwl(eos) => eos.parameters(),
            Eos::TabulatedCompaction(_) => &[],
            Eos::PAlpha(eos) => eos.parameters(),
        }
    }

    /// Reject non-physical constants.
    pub fn validate(&self) -> Result<(), ParameterError> {
        match self {
            Eos::Linear(eos) => eos.validate(),
            Eos::MieGruneisen(eos) => eos.validate(),
            Eos::Polynomial(eos) => eos.validate(),
            Eos::Jwl(eos) => eos.validate(),
            Eos::TabulatedCompaction(eos) => eos.validate(),
            Eos::PAlpha(eos) => eos.validate(),
        }
    }

    /// Isentropic bulk sound speed squared `c^2 = dp/drho|_s` (m^2/s^2) at compression `mu`,
    /// energy `energy` (J/m^3 of reference volume), pressure `pressure`, reference density
    /// `reference_density`. With `dE = p rho0 drho / rho^2` along an isentrope,
    /// `c^2 = (dp/dmu)/rho0 + (dp/dE) p rho0 / rho^2`. For the history-dependent EoS the
    /// terms hold frozen-history derivatives, so this is the elastic (unloading) sound speed:
    /// for P-alpha the porous sound speed at constant distension.
    pub fn sound_speed_squared(
        terms: &EnergyLinearPressure,
        mu: f64,
        energy: f64,
        pressure: f64,
        reference_density: f64,
    ) -> f64 {
        isentropic_stiffness(terms, energy, pressure, 1.0 / (1.0 + mu)) / reference_density
    }
}

/// `rho0 c^2 = dp/dmu + (dp/dE) p V^2`: the bulk sound speed squared of
/// [`Eos::sound_speed_squared`] times the reference density, at relative volume
/// `V = rho0/rho = 1/(1 + mu)` (`rho0 / rho^2 = V^2 / rho0`). No division.
#[inline]
fn isentropic_stiffness(
    terms: &EnergyLinearPressure,
    energy: f64,
    pressure: f64,
    relative_volume: f64,
) -> f64 {
    let at_constant_energy = terms.d_pressure_d_mu(energy);
    // Without energy dependence the second term is zero.
    if terms.energy_coefficient == 0.0 {
        return at_constant_energy;
    }
    at_constant_energy + terms.energy_coefficient * pressure * (relative_volume * relative_volume)
}

/// Longitudinal wave speed for the host's time step: `sqrt(c_bulk^2 + 4G/(3 rho))`, with
/// `c_bulk^2` from [`Eos::sound_speed_squared`] (clamped at 0) and `rho = rho0 / V` at the
/// relative volume `V`: `sqrt((rho0 c_bulk^2 + 4/3 G V) / rho0)`, one division.
pub fn longitudinal_wave_speed(
    terms: &EnergyLinearPressure,
    energy: f64,
    reference_density: f64,
    relative_volume: f64,
    shear_modulus: f64,
) -> f64 {
    let stiffness = isentropic_stiffness(terms, energy, terms.pressure(energy), relative_volume);
    let stiffness = if stiffness > 0.0 { stiffness } else { 0.0 };
    crate::math::sqrt(
        (stiffness + (4.0 / 3.0) * shear_modulus * relative_volume) / reference_density,
    )
}

impl From<LinearEos> for Eos {
    fn from(eos: LinearEos) -> Self {
        Eos::Linear(eos)
    }
}

impl From<MieGruneisen> for Eos {
    fn from(eos: MieGruneisen) -> Self {
        Eos::MieGruneisen(eos)
    }
}

impl From<Polynomial> for Eos {
    fn from(eos: Polynomial) -> Self {
        Eos::Polynomial(eos)
    }
}

impl From<Jwl> for Eos {
    fn from(eos: Jwl) -> Self {
        Eos::Jwl(eos)
    }
}

impl From<TabulatedCompaction> for Eos {
    fn from(eos: TabulatedCompaction) -> Self {
        Eos::TabulatedCompaction(eos)
    }
}

impl From<PAlpha> for Eos {
    fn from(eos: PAlpha) -> Self {
        Eos::PAlpha(eos)
    }
}

impl crate::parameters::ConstantPaths for Eos {
    /// `path`: the constant's name in the variant's family (`solid.<name>` for the P-alpha
    /// solid's); a tabulated EoS has none.
    fn slot(&mut self, path: &str) -> Option<&mut f64> {
        match self {
            Eos::Linear(eos) => eos.named_slot(path),
            Eos::MieGruneisen(eos) => eos.named_slot(path),
            Eos::Polynomial(eos) => eos.named_slot(path),
            Eos::Jwl(eos) => eos.named_slot(path),
            Eos::TabulatedCompaction(_) => None,
            Eos::PAlpha(eos) => match path.strip_prefix("solid.") {
                Some(name) => eos.solid.named_slot(name),
                None => eos.named_slot(path),
            },
        }
    }
}
