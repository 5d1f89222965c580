//! Single-element drivers (no heap). Each drives one material point along a loading path and
//! writes one [`Record`] per step into a caller-provided [`HistorySink`]: a `heapless::Vec`, a
//! `&mut [Record]` through [`SliceSink`], or anything else implementing the trait.
//!
//! Every driver takes any [`PointModel`]: a [`Material`] (J2 metals) or a
//! [`crate::rht::RhtMaterial`] (RHT concrete).
//!
//! Strains are logarithmic (sums of the increments); the relative volume follows as
//! `V = exp(tr eps)`, which is what the kernel's tangent assumes.

mod history;
mod hydrostatic;
mod simple_shear;
mod strain_path;
mod uniaxial_strain;
mod uniaxial_stress;

pub use history::{DriverError, HistorySink, LastRecord, Record, SliceSink};
pub use hydrostatic::{hydrostatic, HydrostaticLoading};
pub use simple_shear::{simple_shear, SimpleShearLoading};
pub use strain_path::{strain_path, PathPoint};
pub use uniaxial_strain::{uniaxial_strain, UniaxialStrainLoading};
pub use uniaxial_stress::{uniaxial_stress, UniaxialStressLoading, LATERAL_TOLERANCE};

use crate::error::{ParameterError, UpdateError};
use crate::material::Material;
use crate::math::exp;
use crate::state::MaterialState;
use crate::tensor::{self, Matrix6, Sym};
use crate::update::{update, update_with_tangent, StepInput, StepOutput};

/// A material model the drivers can drive: one integration point, one step at a time.
/// Implemented by [`Material`] (the J2 metal update, [`crate::update()`]) and by
/// [`crate::rht::RhtMaterial`] (the RHT concrete update).
pub trait PointModel {
    /// Reject invalid constants (called once per driver run).
    fn validate(&self) -> Result<(), ParameterError>;
    /// Elastic shear modulus (Pa), the stress scale of the uniaxial-stress iteration.
    fn shear_modulus(&self) -> f64;
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

/// Apply one strain increment, advance the driver clock and record the result.
pub(crate) fn step_and_record<S: HistorySink + ?Sized>(
    material: &(impl PointModel + ?Sized),
    state: &mut MaterialState,
    total_strain: &mut Sym,
    time: &mut f64,
    increment: &Sym,
    dt: f64,
    sink: &mut S,
) -> Result<StepOutput, DriverError> {
    let input = StepInput {
        strain_increment: *increment,
        dt,
        relative_volume: state.relative_volume * exp(tensor::trace(increment)),
    };
    let output = material
        .update(state, &input)
        .map_err(DriverError::Update)?;
    *total_strain = tensor::add(total_strain, increment);
    *time += dt;
    sink.push(Record::new(*time, total_strain, state, &output))?;
    Ok(output)
}

/// Reject a loading parameter that is not finite or not strictly positive.
pub(crate) fn positive(field: &'static str, value: f64) -> Result<(), DriverError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(DriverError::InvalidLoading { field })
    }
}
