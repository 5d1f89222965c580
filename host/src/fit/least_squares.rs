//! Least-squares fits of a hypothesis (the diagnosis' refits, the calibration's finish): bounded Levenberg-Marquardt (Marquardt 1963, with
//! Marquardt's diagonal scaling) on the whitened residuals of the fitted experiments, in unit
//! coordinates of the bounds, with forward-difference Jacobians. It starts from the calibrated
//! constants (and an added term at its null value), so it is the local recalibration that a
//! nested extension calls for; each iteration costs `p` simulations for the Jacobian and two
//! trial steps run side by side.

use super::engine::Engine;
use super::hypothesis::Hypothesis;
use super::linear::{dot, gram, solve_damped, transpose_times};
use super::FitError;
use serde::{Deserialize, Serialize};

/// Forward-difference step in unit coordinates (1 % of each constant's range).
pub const JACOBIAN_STEP: f64 = 0.01;

/// A least-squares fit.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Fit {
    /// Constants (SI), in the hypothesis's order.
    pub values: Vec<f64>,
    /// The same in unit coordinates.
    pub unit: Vec<f64>,
    /// Whitened residuals of the fitted experiments at `values`.
    pub residuals: Vec<f64>,
    /// Their sum of squares.
    pub chi_square: f64,
    /// Columns `d residuals / d unit` at `values`.
    pub jacobian: Vec<Vec<f64>>,
    /// Iterations taken.
    pub iterations: usize,
}

/// Unit coordinates of `hypothesis`'s bounds to SI.
pub fn to_si(hypothesis: &Hypothesis, unit: &[f64]) -> Vec<f64> {
    hypothesis
        .parameters
        .iter()
        .zip(unit)
        .map(|(p, u)| p.from_unit(*u))
        .collect()
}

/// Whitened residuals at `unit`, or why the simulation failed.
pub fn residuals_at(
    engine: &mut Engine,
    hypothesis: &Hypothesis,
    units: &[Vec<f64>],
    experiments: &[usize],
) -> Result<Vec<Result<Vec<f64>, String>>, FitError> {
    let points: Vec<Vec<f64>> = units.iter().map(|u| to_si(hypothesis, u)).collect();
    let predictions = engine.predict(hypothesis, &points, experiments)?;
    Ok(predictions
        .into_iter()
        .map(|p| p.map(|p| engine.whiten(experiments, &p)))
        .collect())
}

/// Forward-difference Jacobian columns at `unit` (backward at the upper bound); a column whose
/// simulation fails is zero (that constant is then held).
pub fn jacobian(
    engine: &mut Engine,
    hypothesis: &Hypothesis,
    unit: &[f64],
    residuals: &[f64],
    experiments: &[usize],
) -> Result<Vec<Vec<f64>>, FitError> {
    let steps: Vec<f64> = unit
        .iter()
        .map(|u| {
            if u + JACOBIAN_STEP <= 1.0 {
                JACOBIAN_STEP
            } else {
                -JACOBIAN_STEP
            }
        })
        .collect();
    let points: Vec<Vec<f64>> = steps
        .iter()
        .enumerate()
        .map(|(j, h)| {
            let mut u = unit.to_vec();
            u[j] += h;
            u
        })
        .collect();
    let perturbed = residuals_at(engine, hypothesis, &points, experiments)?;
    Ok(perturbed
        .into_iter()
        .zip(&steps)
        .map(|(r, h)| match r {
            Ok(r) => r.iter().zip(residuals).map(|(a, b)| (a - b) / h).collect(),
            Err(_) => vec![0.0; residuals.len()],
        })
        .collect())
}

/// Bounded Levenberg-Marquardt from `start` (SI) over `experiments`, at most `iterations`
/// Jacobians. Stops when an accepted step lowers the chi-square by less than 1e-4 of it.
pub fn levenberg_marquardt(
    engine: &mut Engine,
    hypothesis: &Hypothesis,
    start: &[f64],
    experiments: &[usize],
    iterations: usize,
) -> Result<Fit, FitError> {
    let mut unit: Vec<f64> = hypothesis
        .parameters
        .iter()
        .zip(start)
        .map(|(p, x)| p.to_unit(*x).clamp(0.0, 1.0))
        .collect();
    let mut residuals = residuals_at(engine, hypothesis, std::slice::from_ref(&unit), experiments)?
        .remove(0)
        .map_err(|e| FitError::Simulation(format!("{}: {e}", hypothesis.label)))?;
    let mut chi_square = dot(&residuals, &residuals);
    let mut damping = 1e-3;
    let mut taken = 0;
    let mut jacobian_at_unit: Option<Vec<Vec<f64>>> = None;
    let mut rejections = 0;
    while taken < iterations && !unit.is_empty() {
        let columns = match jacobian_at_unit.take() {
            Some(columns) => columns,
            None => jacobian(engine, hypothesis, &unit, &residuals, experiments)?,
        };
        taken += 1;
        let normal = gram(&columns);
        let gradient: Vec<f64> = transpose_times(&columns, &residuals)
            .iter()
            .map(|g| -g)
            .collect();
        // Two trial dampings side by side: both cores work, and a rejected step costs one
        // batch rather than two.
        let dampings = [damping, 10.0 * damping];
        let trials: Vec<Vec<f64>> = dampings
            .iter()
            .map(|mu| {
                let step =
                    solve_damped(&normal, &gradient, *mu).unwrap_or_else(|| vec![0.0; unit.len()]);
                unit.iter()
                    .zip(&step)
                    .map(|(u, s)| (u + s).clamp(0.0, 1.0))
                    .collect()
            })
            .collect();
        let results = residuals_at(engine, hypothesis, &trials, experiments)?;
        let best = results
            .iter()
            .enumerate()
            .filter_map(|(i, r)| r.as_ref().ok().map(|r| (i, dot(r, r))))
            .filter(|(_, c)| *c < chi_square)
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match best {
            Some((index, trial_chi_square)) => {
                let decrease = chi_square - trial_chi_square;
                unit = trials[index].clone();
                residuals = results[index].clone().unwrap_or_default();
                chi_square = trial_chi_square;
                damping = dampings[index] / 3.0;
                rejections = 0;
                if decrease < 1e-4 * chi_square {
                    break;
                }
            }
            None => {
                // The Jacobian is still the one at `unit`.
                jacobian_at_unit = Some(columns);
                damping *= 100.0;
                rejections += 1;
                if rejections >= 3 {
                    break;
                }
            }
        }
    }
    let columns = match jacobian_at_unit {
        Some(columns) => columns,
        None => jacobian(engine, hypothesis, &unit, &residuals, experiments)?,
    };
    Ok(Fit {
        values: to_si(hypothesis, &unit),
        unit,
        residuals,
        chi_square,
        jacobian: columns,
        iterations: taken,
    })
}
