//! Simulation or material? Before a located misfit is blamed on missing material physics, the
//! experiments that run the FE solver (not a single-element driver) are simulated once more
//! with the same constants another way: the mesh refined (every element size halved) and,
//! where the kind has a second solver, on the other solver ([`crate::experiment::Setup::refined`],
//! [`crate::experiment::Setup::other_solver`]). If the predictions move by more than the
//! recorded uncertainty, the misfit of that experiment is at least partly the simulation's, and
//! the diagnosis says so instead of changing the material for it.
//!
//! The measure: the RMS over the recorded points of `(p_other - p) / sigma`, with `sigma` each
//! point's recorded uncertainty. It is compared with 1 (the predictions move by more than the
//! recording can resolve) and with the misfit's own RMS whitened residual (the share of the
//! misfit the method could account for).

use super::locate::ExperimentMisfit;
use crate::experiment::Experiment;
use crate::fit::{Engine, Hypothesis};
use crate::input::InputError;
use serde::{Deserialize, Serialize};

/// One experiment simulated another way.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct NumericalCheck {
    /// Index in the campaign.
    pub experiment: usize,
    /// Display name.
    pub name: String,
    /// What was changed ("elements of 0.200 mm instead of 0.400", "the multi-material
    /// Eulerian solver").
    pub change: String,
    /// RMS over the recorded points of the prediction's shift in recorded uncertainties (none:
    /// the other simulation failed).
    pub shift: Option<f64>,
    /// RMS whitened residual of the misfit being checked.
    pub misfit: f64,
    /// The shift exceeds the recorded uncertainty: the simulation is not converged (a mesh
    /// change) or depends on the method (a solver change).
    pub numerical: bool,
    /// Why the other simulation failed, if it did.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failure: Option<String>,
}

/// The RMS of `(other - base) / sigma` over the points (none if any is not finite).
fn shift(base: &[f64], other: &[f64], sigmas: &[f64]) -> Option<f64> {
    let n = base.len().min(other.len()).min(sigmas.len());
    if n == 0 {
        return None;
    }
    let sum: f64 = (0..n)
        .map(|i| {
            let d = (other[i] - base[i]) / sigmas[i];
            d * d
        })
        .sum();
    let rms = libm::sqrt(sum / n as f64);
    rms.is_finite().then_some(rms)
}

/// Simulate each located (structured) fitted experiment of `misfits` that has a mesh or a
/// second solver once more with `hypothesis`'s constants, refined and on the other solver,
/// against `base` (the predictions at those constants). A variant whose set-up fails the
/// kind's up-front checks (the run budget: a refined mesh over the element or element-cycle
/// limit) is not run; its check records why.
pub fn check(
    engine: &Engine,
    hypothesis: &Hypothesis,
    base: &[Vec<f64>],
    misfits: &[ExperimentMisfit],
) -> Result<Vec<NumericalCheck>, String> {
    let values = hypothesis.values()?;
    let realised = hypothesis.realise(&values)?;
    let mut checks = Vec::new();
    for misfit in misfits.iter().filter(|m| m.structured && !m.holdout) {
        let experiment = &engine.experiments[misfit.index];
        let setup = &experiment.file.setup;
        let whitened: Vec<f64> = misfit.residuals.iter().map(|r| r.whitened).collect();
        let misfit_rms =
            libm::sqrt(whitened.iter().map(|w| w * w).sum::<f64>() / whitened.len().max(1) as f64);
        let sigmas: Vec<f64> = experiment.recording.iter().map(|p| p.uncertainty).collect();
        for (change, other) in [setup.refined(), setup.other_solver()]
            .into_iter()
            .flatten()
        {
            let mut variant: Experiment = experiment.clone();
            variant.file.setup = other;
            // The variant's sizes (elements, steps, element-cycles) pass the same up-front
            // checks as a loaded file, so a refined mesh beyond the run budget is refused
            // with its reason instead of run.
            let check = |field: &str, ok: bool, message: &str| {
                if ok {
                    Ok(())
                } else {
                    Err(InputError::Field {
                        path: experiment.path.clone(),
                        line: None,
                        field: field.to_string(),
                        message: format!("{change}: {message}"),
                    })
                }
            };
            let checked = variant.file.setup.validate(&check);
            let (shift, failure) = match checked {
                Err(error) => (None, Some(error.to_string())),
                Ok(()) => match realised.predict(&variant, engine.settings()) {
                    Ok(predicted) => (shift(&base[misfit.index], &predicted, &sigmas), None),
                    Err(error) => (None, Some(error)),
                },
            };
            checks.push(NumericalCheck {
                experiment: misfit.index,
                name: misfit.name.clone(),
                change,
                shift,
                misfit: misfit_rms,
                numerical: shift.is_some_and(|s| s > 1.0),
                failure,
            });
        }
    }
    Ok(checks)
}

#[cfg(test)]
mod tests {
    use super::shift;

    #[test]
    fn the_shift_is_the_rms_of_the_moves_in_recorded_uncertainties() {
        // GOAL: the measure of "moves by more than its uncertainty".
        // SETUP: two points, sigma 1 and 2, moved by 3 and 4.
        // REFERENCE: sqrt((3^2 + 2^2) / 2) = sqrt(6.5).
        let s = shift(&[1.0, 1.0], &[4.0, 5.0], &[1.0, 2.0]).unwrap();
        assert!((s - 6.5_f64.sqrt()).abs() < 1e-15);
        assert_eq!(shift(&[], &[], &[]), None);
        assert_eq!(shift(&[1.0], &[f64::NAN], &[1.0]), None);
    }
}
