//! Hydrostatic loading and unloading: equal normal strains, compressed to a volumetric strain
//! and released back to the initial volume at the same rate.

use super::{positive, step_and_record, DriverError, HistorySink, PointModel};
use crate::state::MaterialState;
use crate::tensor;

/// Loading of the hydrostatic driver.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HydrostaticLoading {
    /// Peak volumetric compression `-ln(V/V0)` (> 0).
    pub peak_compression: f64,
    /// Volumetric strain rate magnitude (1/s), `> 0`.
    pub strain_rate: f64,
    /// Steps of the loading branch.
    pub loading_steps: u32,
    /// Steps of the unloading branch (back to `V = V0`); 0 for loading only.
    pub unloading_steps: u32,
}

/// Drive `state` through hydrostatic loading then unloading; one record per step.
pub fn hydrostatic<S: HistorySink + ?Sized>(
    material: &(impl PointModel + ?Sized),
    state: &mut MaterialState,
    loading: &HydrostaticLoading,
    sink: &mut S,
) -> Result<(), DriverError> {
    material.validate().map_err(DriverError::Parameter)?;
    positive("peak_compression", loading.peak_compression)?;
    positive("strain_rate", loading.strain_rate)?;
    positive("loading_steps", f64::from(loading.loading_steps))?;
    let mut total_strain = tensor::ZERO;
    let mut time = 0.0;
    let branches = [
        (loading.loading_steps, -1.0),
        (loading.unloading_steps, 1.0),
    ];
    for (steps, sign) in branches {
        if steps == 0 {
            continue;
        }
        let volumetric_increment = loading.peak_compression / f64::from(steps);
        let dt = volumetric_increment / loading.strain_rate;
        let normal = sign * volumetric_increment / 3.0;
        let increment = [normal, normal, normal, 0.0, 0.0, 0.0];
        for _ in 0..steps {
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
    }
    Ok(())
}
