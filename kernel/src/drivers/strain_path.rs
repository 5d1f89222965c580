//! A general prescribed strain path with temperature (the MTest-style driver): piecewise
//! linear total log strain between points, each segment cut into equal sub-steps; where a
//! point prescribes a temperature, the temperature is interpolated and imposed before each
//! sub-step (overriding heating), otherwise it evolves with the material's heating.

use super::{positive, step_and_record, DriverError, HistorySink, PointModel};
use crate::state::MaterialState;
use crate::tensor::{self, Sym};

/// One vertex of the path.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PathPoint {
    /// Time (s); strictly increasing along the path.
    pub time: f64,
    /// Total log strain, Voigt, tensor shear.
    pub strain: Sym,
    /// Imposed temperature (K), or `None` to let it evolve.
    pub temperature: Option<f64>,
}

/// Drive `state` along `path` (starting from zero strain at `path[0]`, which must be the
/// zero-strain start), `substeps` steps per segment.
pub fn strain_path<S: HistorySink + ?Sized>(
    material: &(impl PointModel + ?Sized),
    state: &mut MaterialState,
    path: &[PathPoint],
    substeps: u32,
    sink: &mut S,
) -> Result<(), DriverError> {
    material.validate().map_err(DriverError::Parameter)?;
    positive("substeps", f64::from(substeps))?;
    if path.len() < 2 {
        return Err(DriverError::InvalidLoading { field: "path" });
    }
    let mut total_strain = tensor::ZERO;
    let mut time = path[0].time;
    for pair in path.windows(2) {
        let (start, end) = (&pair[0], &pair[1]);
        positive("time (increasing)", end.time - start.time)?;
        if !crate::math::all_finite(&end.strain) {
            return Err(DriverError::InvalidLoading { field: "strain" });
        }
        let count = f64::from(substeps);
        let dt = (end.time - start.time) / count;
        for k in 1..=substeps {
            let fraction = f64::from(k) / count;
            if let (Some(t0), Some(t1)) = (start.temperature, end.temperature) {
                state.temperature = t0 + (t1 - t0) * (f64::from(k - 1) / count);
            }
            let target: Sym = core::array::from_fn(|i| {
                start.strain[i] + (end.strain[i] - start.strain[i]) * fraction
            });
            let increment: Sym = core::array::from_fn(|i| target[i] - total_strain[i]);
            step_and_record(
                material,
                state,
                &mut total_strain,
                &mut time,
                &increment,
                dt,
                sink,
            )?;
            total_strain = target;
        }
    }
    Ok(())
}
