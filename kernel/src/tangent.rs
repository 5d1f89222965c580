//! The algorithmic tangent `d sigma_{n+1} / d deps` of a point model without a closed-form
//! one, by central differences of its whole update (RHT, K&C concrete).

use crate::error::UpdateError;
use crate::math::exp;
use crate::point_model::StepInput;
use crate::tensor::{Matrix6, Sym};

/// Relative size of the strain perturbation of [`central_difference_tangent`].
pub const TANGENT_PERTURBATION: f64 = 1e-6;

/// Write into `tangent` the central-difference derivative of the stress that `stress_after`
/// computes from `input` (12 evaluations). The perturbation of column `j` is
/// [`TANGENT_PERTURBATION`] times the largest strain increment component (at least `1e-12`);
/// normal columns also perturb the relative volume as `V1 exp(h)`, the host's
/// `V1 = V0 exp(tr deps)`. At a kink of the response (onset of yield, of softening) it is
/// the average of the two one-sided slopes. Meant as a Newton Jacobian for drivers and
/// implicit callers.
pub fn central_difference_tangent(
    input: &StepInput,
    mut stress_after: impl FnMut(&StepInput) -> Result<Sym, UpdateError>,
    tangent: &mut Matrix6,
) -> Result<(), UpdateError> {
    let largest =
        input
            .strain_increment
            .iter()
            .fold(0.0_f64, |m, x| if x.abs() > m { x.abs() } else { m });
    let h = TANGENT_PERTURBATION * if largest > 1e-6 { largest } else { 1e-6 };
    for j in 0..6 {
        let mut columns = [[0.0; 6]; 2];
        for (column, sign) in columns.iter_mut().zip([1.0, -1.0]) {
            let mut perturbed = *input;
            perturbed.strain_increment[j] += sign * h;
            if j < 3 {
                perturbed.relative_volume = input.relative_volume * exp(sign * h);
            }
            *column = stress_after(&perturbed)?;
        }
        for (i, row) in tangent.iter_mut().enumerate() {
            row[j] = (columns[0][i] - columns[1][i]) / (2.0 * h);
        }
    }
    Ok(())
}
