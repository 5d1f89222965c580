//! The material model of one integration point, one step at a time: the trait every law
//! implements (the J2 metals here, RHT in `rht/`, K&C in `kc/`, either per part in
//! `part_material`), and what the single-element drivers and a host FE code (stoss's own
//! solvers among them) call.

use crate::error::{ParameterError, UpdateError};
use crate::material::Material;
use crate::state::{MaterialState, StateFlags};
use crate::tensor::Matrix6;
use crate::update::{update, update_with_tangent, StepInput, StepOutput};

/// A material model at one integration point, one step at a time: what the drivers and a
/// host FE code (stoss's own explicit solver among them) need of it. Implemented by
/// [`Material`] (the J2 metal update, [`crate::update()`]), by
/// [`crate::rht::RhtMaterial`] (the RHT concrete update) and by [`crate::PartMaterial`]
/// (either, chosen per part).
pub trait PointModel {
    /// Reject invalid constants (called once per driver run).
    fn validate(&self) -> Result<(), ParameterError>;
    /// Elastic shear modulus (Pa), the stress scale of the uniaxial-stress iteration.
    fn shear_modulus(&self) -> f64;
    /// Reference density `rho0` (kg/m^3), for the host's lumped mass.
    fn density(&self) -> f64;
    /// A fresh, stress-free state at `temperature` (K), with the EoS history seeded (P-alpha
    /// starts at its initial distension).
    fn initial_state(&self, temperature: f64) -> MaterialState;
    /// For a criterion that needs the element's total strain, which only the host knows
    /// (Autodyn's geometric erosion strain, a principal-strain failure): the smallest
    /// magnitude of a principal logarithmic strain at which one can be met (see
    /// [`crate::damage::Failure::kinematic_strain_bound`]); `None` without such a criterion.
    fn kinematic_strain_bound(&self) -> Option<f64> {
        None
    }
    /// The flags those criteria set for an element with principal logarithmic strains
    /// `principal_strains` (see [`crate::damage::Failure::kinematic_flags`]).
    fn kinematic_flags(&self, _principal_strains: [f64; 3]) -> StateFlags {
        StateFlags(0)
    }
    /// Update `state` over one step; on error `state` is unchanged.
    fn update(
        &self,
        state: &mut MaterialState,
        input: &StepInput,
    ) -> Result<StepOutput, UpdateError>;
    /// [`PointModel::update`] that also writes `d sigma / d deps` into `tangent`.
    fn update_with_tangent(
        &self,
        state: &mut MaterialState,
        input: &StepInput,
        tangent: &mut Matrix6,
    ) -> Result<StepOutput, UpdateError>;
}

impl PointModel for Material {
    fn validate(&self) -> Result<(), ParameterError> {
        Material::validate(self)
    }

    fn shear_modulus(&self) -> f64 {
        self.shear_modulus
    }

    fn density(&self) -> f64 {
        self.density
    }

    fn initial_state(&self, temperature: f64) -> MaterialState {
        let mut state = MaterialState::initial(temperature);
        state.eos_history = self.eos.initial_history();
        state
    }

    fn kinematic_strain_bound(&self) -> Option<f64> {
        self.failure.kinematic_strain_bound()
    }

    fn kinematic_flags(&self, principal_strains: [f64; 3]) -> StateFlags {
        self.failure.kinematic_flags(principal_strains)
    }

    #[inline]
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

impl<T: PointModel + ?Sized> PointModel for &T {
    fn validate(&self) -> Result<(), ParameterError> {
        (**self).validate()
    }

    fn shear_modulus(&self) -> f64 {
        (**self).shear_modulus()
    }

    fn density(&self) -> f64 {
        (**self).density()
    }

    fn initial_state(&self, temperature: f64) -> MaterialState {
        (**self).initial_state(temperature)
    }

    fn kinematic_strain_bound(&self) -> Option<f64> {
        (**self).kinematic_strain_bound()
    }

    fn kinematic_flags(&self, principal_strains: [f64; 3]) -> StateFlags {
        (**self).kinematic_flags(principal_strains)
    }

    fn update(
        &self,
        state: &mut MaterialState,
        input: &StepInput,
    ) -> Result<StepOutput, UpdateError> {
        (**self).update(state, input)
    }

    fn update_with_tangent(
        &self,
        state: &mut MaterialState,
        input: &StepInput,
        tangent: &mut Matrix6,
    ) -> Result<StepOutput, UpdateError> {
        (**self).update_with_tangent(state, input, tangent)
    }
}
