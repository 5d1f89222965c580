//! Uniaxial strain: `eps_xx` prescribed at constant rate, all other strains zero (the state of
//! a plate-impact or confined test).

use super::{positive, step_and_record, DriverError, HistorySink, PointModel};
use crate::state::MaterialState;
use crate::tensor;

/// Loading of the uniaxial-strain driver.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct UniaxialStrainLoading {
    /// Axial true strain rate magnitude (1/s), `> 0`.
    pub strain_rate: f64,
    /// Final axial log strain; negative for compression.
    pub final_strain: f64,
    /// Number of equal steps.
    pub steps: u32,
}

/// Drive `state` in uniaxial strain; one record per step.
pub fn uniaxial_strain<S: HistorySink + ?Sized>(
    material: &(impl PointModel + ?Sized),
    state: &mut MaterialState,
    loading: &UniaxialStrainLoading,
    sink: &mut S,
) -> Result<(), DriverError> {
    material.validate().map_err(DriverError::Parameter)?;
    positive("strain_rate", loading.strain_rate)?;
    positive("final_strain (magnitude)", loading.final_strain.abs())?;
    positive("steps", f64::from(loading.steps))?;
    let axial_increment = loading.final_strain / f64::from(loading.steps);
    let dt = axial_increment.abs() / loading.strain_rate;
    let increment = [axial_increment, 0.0, 0.0, 0.0, 0.0, 0.0];
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
