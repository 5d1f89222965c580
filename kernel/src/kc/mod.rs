//! The Karagozian & Case concrete model, release III (Malvar, Crawford, Wesevich & Simons,
//! "A plasticity concrete material model for DYNA3D", Int. J. Impact Eng. 19 (1997)
//! 847-873; LS-DYNA `*MAT_CONCRETE_DAMAGE_REL3`, Schwer & Malvar 2005), as seed 001
//! (FOI-R--0281--SE, 2001) chapter 5 uses it for the reinforced-concrete beam: three fixed
//! surfaces, a tabulated damage function, a tabulated EoS, rate enhancement and a crack band.
//!
//! # Equations (strengths `Delta sigma = sqrt(3 J2)`, `p` positive in compression)
//!
//! ```text
//! maximum    Delta sigma_m = a0 + p/(a1 + a2 p)            (p >= fc/3)
//! yield      Delta sigma_y = a0y + p/(a1y + a2y p)          (p >= fyc/3)
//! residual   Delta sigma_r = p/(a1f + a2f p)
//! current    Delta sigma   = Delta sigma_y + eta (Delta sigma_m - Delta sigma_y)   lambda <= lambda_m
//!                          = Delta sigma_r + eta (Delta sigma_m - Delta sigma_r)   lambda >  lambda_m
//!            (seed 001 eq. 4.1 of chapter 5), times the Willam-Warnke factor r(theta, psi(p))
//! damage     d lambda = d eps_p / (r_f (1 + p/(r_f ft))^b1)   p >= 0   (seed eq. 4.2)
//!                     = d eps_p / (r_f (1 + p/(r_f ft))^b2)   p <  0
//! rate       Delta sigma(p) -> r_f Delta sigma(p / r_f)
//! ```
//!
//! # What was restored, and from what
//! - **Low pressures and tension** (not in the seed): below `p = fc/3` the tensile meridian is
//!   the line `3/2 (p + ft)` through uniaxial tension and the compressive meridian is it over
//!   `psi(p)`; the yield surface is `1.35 ft + 3 p (1 - 1.35 ft/fyc)` there and `1.35 (p +
//!   ft)` in tension; `psi(p)` is piecewise linear through 1/2 (tension), `1/2 + 3/2 ft/fc`
//!   (uniaxial compression), the biaxial point (`alpha` = 1.15), 0.753 at `3 fc` and 1 at
//!   `8.45 fc` (the release-III construction, Malvar et al. 1997, Schwer & Malvar 2005).
//! - **Softening in tension**: after the peak the tensile side of the surface is the maximum
//!   one scaled about the origin by `eta`, `3 (p + eta ft)`, so the hydrostatic tensile
//!   strength falls with the deviatoric one; the pressure is cut off there. stoss's choice,
//!   which makes uniaxial-tension softening `sigma = eta ft` exactly.
//! - **The meridians from `fc`**: by similarity with Malvar's 45.4 MPa reference set
//!   ([`KcParameters::from_strength`]); LS-DYNA's generator polynomials are not printed in the
//!   sources here.
//! - **Crack band** (seed 001 sec. 5.2.1, FOI's modification): after the peak the growth of
//!   `lambda` is scaled by the element size over a reference size, so the energy released
//!   per unit crack area does not depend on the mesh ([`CrackBand`]). For table 5.3 and
//!   `Gf` = 156 N/m the reference size is 10.6 mm, the beam's element size at the impact.
//!
//! # Not modelled (say so where it matters)
//! - The volumetric damage term `b3 f_d k_d (eps_v - eps_v,yield)` of seed eq. 4.2 (damage
//!   under near-hydrostatic tension): hydrostatic tension is limited by the cut-off only.
//! - Dilatancy: the return is radial at fixed pressure (LS-DYNA's `omega = 0`; release III's
//!   default is 0.5).
//!
//! # State
//! [`MaterialState::plastic_strain`] holds the damage parameter `lambda` (the model needs
//! no other plastic strain), [`MaterialState::damage`] the scaled damage measure of LS-DYNA
//! halved to `[0, 1]` ([`damage_measure`]), [`MaterialState::eos_history`] the EoS's largest
//! compression. [`StateFlags::FAILED`] means only the residual strength is left (`eta = 0`
//! after the peak).

mod parameters;
mod surfaces;
mod update;

pub use parameters::{CrackBand, DamageFunction, KcParameters, RateEnhancement, MAX_DAMAGE_POINTS};
pub use surfaces::Strengths;
pub use update::{damage_measure, update, update_with_tangent};

use crate::damage::Failure;
use crate::eos::{Eos, TabulatedCompaction};
use crate::error::{check, ParameterError, UpdateError};
use crate::point_model::PointModel;
use crate::point_model::{StepInput, StepOutput};
use crate::state::{MaterialState, StateFlags};
use crate::tensor::Matrix6;

/// A complete K&C material: density, constants, EoS, erosion.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct KcMaterial {
    /// Reference density `rho0` (kg/m^3).
    pub density: f64,
    /// Strength, damage, rate and crack-band constants.
    pub parameters: KcParameters,
    /// Equation of state (K&C's is tabulated: [`Eos::TabulatedCompaction`]).
    pub eos: Eos,
    /// Autodyn-style instantaneous geometric strain at which the host erodes the element;
    /// `None`: never.
    #[cfg_attr(feature = "serde", serde(default))]
    pub erosion_geometric_strain: Option<f64>,
}

impl KcMaterial {
    /// Seed 001 chapter 5's concrete: table 5.1 (2420 kg/m^3, fc 100 MPa, ft 5.2 MPa, E 44
    /// GPa, nu 0.16), damage function of table 5.3, the tabulated EoS of table 5.2
    /// ([`TabulatedCompaction::CONCRETE_FOI_TABLE_5_2`]), CEB-FIP rates, no crack band and
    /// no erosion ([`KcParameters::HPC_100MPA_FOI`]).
    pub const HPC_100MPA_FOI: KcMaterial = KcMaterial {
        density: 2420.0,
        parameters: KcParameters::HPC_100MPA_FOI,
        eos: Eos::TabulatedCompaction(TabulatedCompaction::CONCRETE_FOI_TABLE_5_2),
        erosion_geometric_strain: None,
    };

    /// A fresh state at `temperature` (K) with the EoS history seeded.
    pub fn initial_state(&self, temperature: f64) -> MaterialState {
        let mut state = MaterialState::initial(temperature);
        state.eos_history = self.eos.initial_history();
        state
    }

    /// Validate every part; the first offending field is reported.
    pub fn validate(&self) -> Result<(), ParameterError> {
        check::positive("density", self.density)?;
        self.parameters.validate()?;
        self.eos.validate()?;
        if let Some(strain) = self.erosion_geometric_strain {
            check::positive("erosion_geometric_strain", strain)?;
        }
        Ok(())
    }

    fn kinematic_failure(&self) -> Failure {
        Failure {
            erosion_geometric_strain: self.erosion_geometric_strain,
            ..Failure::NONE
        }
    }
}

impl PointModel for KcMaterial {
    fn validate(&self) -> Result<(), ParameterError> {
        KcMaterial::validate(self)
    }

    fn shear_modulus(&self) -> f64 {
        self.parameters.shear_modulus
    }

    fn density(&self) -> f64 {
        self.density
    }

    fn initial_state(&self, temperature: f64) -> MaterialState {
        KcMaterial::initial_state(self, temperature)
    }

    fn kinematic_strain_bound(&self) -> Option<f64> {
        self.kinematic_failure().kinematic_strain_bound()
    }

    fn kinematic_flags(&self, principal_strains: [f64; 3]) -> StateFlags {
        self.kinematic_failure().kinematic_flags(principal_strains)
    }

    fn update(
        &self,
        state: &mut MaterialState,
        input: &StepInput,
    ) -> Result<StepOutput, UpdateError> {
        update(self, state, input)
    }

    fn update_with_tangent(
        &self,
        state: &mut MaterialState,
        input: &StepInput,
        tangent: &mut Matrix6,
    ) -> Result<StepOutput, UpdateError> {
        update_with_tangent(self, state, input, tangent)
    }
}
