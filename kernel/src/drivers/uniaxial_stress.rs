//! Uniaxial stress at constant axial true strain rate: `eps_xx` prescribed, `sigma_yy =
//! sigma_zz = 0` enforced each step by Newton iteration on the lateral strain increments with
//! the consistent tangent (shear strains zero).

use super::{positive, step_and_record, DriverError, HistorySink, PointModel};
use crate::point_model::StepInput;
use crate::state::MaterialState;
use crate::tensor::{self, solve2, Matrix6};

/// Lateral stress accepted as zero, relative to `max(|sigma_xx|, 1e-6 G)`.
pub const LATERAL_TOLERANCE: f64 = 1e-13;

/// Newton iterations allowed for the lateral stresses per step.
const MAX_LATERAL_ITERATIONS: u32 = 30;

/// Loading of the uniaxial-stress driver.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct UniaxialStressLoading {
    /// Axial true strain rate magnitude (1/s), `> 0`.
    pub strain_rate: f64,
    /// Final axial log strain; negative for compression.
    pub final_strain: f64,
    /// Number of equal steps.
    pub steps: u32,
}

/// Drive `state` in uniaxial stress; one record per step.
pub fn uniaxial_stress<S: HistorySink + ?Sized>(
    material: &(impl PointModel + ?Sized),
    state: &mut MaterialState,
    loading: &UniaxialStressLoading,
    sink: &mut S,
) -> Result<(), DriverError> {
    material.validate().map_err(DriverError::Parameter)?;
    positive("strain_rate", loading.strain_rate)?;
    positive("final_strain (magnitude)", loading.final_strain.abs())?;
    positive("steps", f64::from(loading.steps))?;
    let axial_increment = loading.final_strain / f64::from(loading.steps);
    let dt = axial_increment.abs() / loading.strain_rate;
    let shear = material.shear_modulus();
    // Elastic Poisson ratio as the first lateral guess; later steps reuse the last ratio.
    let mut lateral_ratio = -0.3;
    let mut total_strain = tensor::ZERO;
    let mut time = 0.0;
    for _ in 0..loading.steps {
        let mut lateral = [lateral_ratio * axial_increment; 2];
        let mut converged = None;
        let mut best: Option<(f64, [f64; 2])> = None;
        for _ in 0..MAX_LATERAL_ITERATIONS {
            let increment = [axial_increment, lateral[0], lateral[1], 0.0, 0.0, 0.0];
            let mut trial = *state;
            let mut tangent: Matrix6 = [[0.0; 6]; 6];
            let input = StepInput {
                strain_increment: increment,
                dt,
                relative_volume: state.relative_volume
                    * crate::math::exp(tensor::trace(&increment)),
            };
            material
                .update_with_tangent(&mut trial, &input, &mut tangent)
                .map_err(DriverError::Update)?;
            let residual = [trial.stress[1], trial.stress[2]];
            let scale = {
                let axial = trial.stress[0].abs();
                if axial > 1e-6 * shear {
                    axial
                } else {
                    1e-6 * shear
                }
            };
            let size = residual[0].abs().max(residual[1].abs()) / scale;
            if best.is_none_or(|(b, _)| size < b) {
                best = Some((size, lateral));
            }
            if size <= LATERAL_TOLERANCE {
                converged = Some(lateral);
                break;
            }
            let jacobian = [
                [tangent[1][1], tangent[1][2]],
                [tangent[2][1], tangent[2][2]],
            ];
            let Some(correction) = solve2(jacobian, [-residual[0], -residual[1]]) else {
                break;
            };
            lateral = [lateral[0] + correction[0], lateral[1] + correction[1]];
        }
        // Round-off can stall Newton just above the tolerance; accept a stalled iterate that is
        // within 1e3 of it, otherwise report divergence.
        let lateral = match (converged, best) {
            (Some(lateral), _) => lateral,
            (None, Some((size, lateral))) if size <= 1e3 * LATERAL_TOLERANCE => lateral,
            _ => return Err(DriverError::LateralIterationDiverged),
        };
        if axial_increment != 0.0 {
            lateral_ratio = 0.5 * (lateral[0] + lateral[1]) / axial_increment;
        }
        let increment = [axial_increment, lateral[0], lateral[1], 0.0, 0.0, 0.0];
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
