//! J2 (von Mises) metals: a complete material ([`material`]: density, elasticity, strength,
//! heating, EoS, failure), its stress update for one point and one step ([`update`](mod@update):
//! EoS, elastic predictor, implicit or lagged radial return, heating, damage, the consistent
//! tangent and the wave speed) and its [`PointModel`] implementation.

pub mod lanes;
pub mod material;
pub mod update;

pub use lanes::{update_block, update_lanes};
pub use material::{Heating, Material, RateTreatment};
pub use update::{update, update_with_tangent};

use crate::error::{ParameterError, UpdateError};
use crate::point_model::{PointModel, StepInput, StepOutput, LANES};
use crate::state::{MaterialState, StateFlags};
use crate::tensor::Matrix6;

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

    #[inline]
    fn update_lanes(
        &self,
        states: &mut [MaterialState; LANES],
        inputs: &[StepInput; LANES],
        results: &mut [Result<StepOutput, UpdateError>; LANES],
    ) {
        update_lanes(self, states, inputs, results)
    }
}
