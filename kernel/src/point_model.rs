//! The material model of one integration point, one step at a time: the trait every law
//! implements (the J2 metals in `j2/`, RHT in `rht/`, K&C in `kc/`, either per part in
//! `part_material`), what the single-element drivers and a host FE code (stoss's own solvers
//! among them) call, and the step's input and output every law shares.

use crate::error::{ParameterError, UpdateError};
use crate::state::{MaterialState, StateFlags};
use crate::tensor::{Matrix6, Sym};

/// Points a group update advances together ([`PointModel::update_lanes`]).
pub const LANES: usize = 8;

/// A material model at one integration point, one step at a time: what the drivers and a
/// host FE code (stoss's own explicit solver among them) need of it. Implemented by
/// [`crate::Material`] (the J2 metal update, [`crate::update()`]), by
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
    /// [`PointModel::update`] of [`LANES`] independent points, `states[i]` over `inputs[i]`
    /// into `results[i]`, bit for bit as one at a time (which is what this default does; the
    /// J2 metals advance the group stage by stage, `crate::j2::lanes`).
    #[inline]
    fn update_lanes(
        &self,
        states: &mut [MaterialState; LANES],
        inputs: &[StepInput; LANES],
        results: &mut [Result<StepOutput, UpdateError>; LANES],
    ) {
        for ((state, input), result) in states.iter_mut().zip(inputs).zip(results.iter_mut()) {
            *result = self.update(state, input);
        }
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

    #[inline]
    fn update_lanes(
        &self,
        states: &mut [MaterialState; LANES],
        inputs: &[StepInput; LANES],
        results: &mut [Result<StepOutput, UpdateError>; LANES],
    ) {
        (**self).update_lanes(states, inputs, results)
    }
}

/// What the host gives for one step.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StepInput {
    /// Strain increment, Voigt order, **tensor** shear (Jaumann/Green-Naghdi-rotated by the host).
    pub strain_increment: Sym,
    /// Time step (s), `> 0`.
    pub dt: f64,
    /// Relative volume `V/V0` at the end of the step, `> 0`.
    pub relative_volume: f64,
}

/// Per-step results besides the updated state.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StepOutput {
    /// Longitudinal wave speed (m/s) for the host's CFL time step.
    pub wave_speed: f64,
    /// Plastic multiplier `dl` = equivalent plastic strain increment of this step.
    pub plastic_increment: f64,
    /// Flow stress used in the return (Pa); the current flow stress if elastic.
    pub yield_stress: f64,
    /// Return-mapping iterations (0 if elastic or lagged).
    pub iterations: u32,
}
