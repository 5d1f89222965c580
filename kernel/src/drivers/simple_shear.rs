//! Simple shear: tensor shear strain `eps_xy` prescribed at constant rate, all other strains
//! zero. The kernel receives unrotated increments (small-rotation simple shear; a host would
//! rotate the stress objectively first).

use super::{positive, step_and_record, DriverError, HistorySink, PointModel};
use crate::state::MaterialState;
use crate::tensor;

/// Loading of the simple-shear driver.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SimpleShearLoading {
    /// Tensor shear strain rate `d eps_xy/dt` (1/s), `> 0`.
    pub shear_rate: f64,
    /// Final tensor shear strain `eps_xy` (= gamma/2).
    pub final_shear_strain: f64,
    /// Number of equal steps.
    pub steps: u32,
}

/// Drive `state` in simple shear; one record per step.
pub fn simple_shear<S: HistorySink + ?Sized>(
    material: &(impl PointModel + ?Sized),
    state: &mut MaterialState,
    loading: &SimpleShearLoading,
    sink: &mut S,
) -> Result<(), DriverError> {
    material.validate().map_err(DriverError::Parameter)?;
    positive("shear_rate", loading.shear_rate)?;
    positive(
        "final_shear_strain (magnitude)",
        loading.final_shear_strain.abs(),
    )?;
    positive("steps", f64::from(loading.steps))?;
    let shear_increment = loading.final_shear_strain / f64::from(loading.steps);
    let dt = shear_increment.abs() / loading.shear_rate;
    let increment = [0.0, 0.0, 0.0, shear_increment, 0.0, 0.0];
    let mut total_strain = tensor::ZERO;
    let mut time = 0.0;
    for _ in 0..loading.steps {
        step_and_record(
            material,
            state,
            &mut total_strain,
            &mut time,
            &increment,
            dt,
            sink,
        )?;
    }
    Ok(())
}
