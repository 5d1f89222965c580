//! Single-element drivers (no heap). Each drives one material point along a loading path and
//! writes one [`Record`] per step into a caller-provided [`HistorySink`]: a `heapless::Vec`, a
//! `&mut [Record]` through [`SliceSink`], or anything else implementing the trait.
//!
//! Every driver takes any [`PointModel`]: a [`crate::Material`] (J2 metals) or a
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

use crate::math::exp;
use crate::point_model::PointModel;
use crate::point_model::{StepInput, StepOutput};
use crate::state::MaterialState;
use crate::tensor::{self, Sym};

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
