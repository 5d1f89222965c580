//! How well the recordings determine the calibrated constants: the linearised (Gauss-Newton)
//! covariance of the weighted least-squares problem at the selected constants.
//!
//! With the weighted residuals `r_k = sqrt(w_e) (y_k - m_k(theta)) / sigma_k` of every
//! recorded point `k` of the fitted experiments (weight `w_e` of its experiment, uncertainty
//! `sigma_k`) and their Jacobian `J = dr/dtheta` by forward differences (step 1e-3 of each
//! constant's search range), the covariance is `C = s^2 (J^T J)^-1` with the reduced
//! chi-square `s^2 = r.r / (n - p)` (the recorded uncertainties scaled so that the fit is
//! one sigma per point; Bard 1974, *Nonlinear parameter estimation*, ch. 7). Reported: the
//! 95 % half-widths `1.96 sqrt(C_ii)`; every pair with a correlation `|rho| >= 0.95`, which
//! these experiments cannot tell apart; and every constant whose variance inflation factor
//! `VIF_i = (J^T J)_ii (J^T J)^-1_ii >= 10` (the usual collinearity threshold: a multiple
//! correlation with the other constants above 0.95), which is determined only in combination
//! with others (JC's A, B and n from flow curves over a narrow strain range are the classic
//! case; no pair of them need reach 0.95). The calibration minimises a range- or
//! magnitude-scaled RMSE, not this chi-square, and the intervals are local: along a curved
//! valley of the misfit (A-B-n) the constants can sit several half-widths from the truth while the fit is at the
//! noise floor. Read them as the recordings' information near the selected point.

use super::campaign::Campaign;
use crate::fit::ModelSpace;
use crate::solver::SolverSettings;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Correlation above which two constants are reported as not separately identifiable.
pub const IDENTIFIABLE_CORRELATION: f64 = 0.95;

/// Variance inflation factor above which a constant is reported as determined only in
/// combination with others.
pub const COLLINEAR_VIF: f64 = 10.0;

/// Forward-difference step, as a fraction of each constant's search range.
const STEP: f64 = 1.0e-3;

/// The linearised uncertainty of a model's calibrated constants.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Uncertainty {
    /// 95 % half-width of each constant (SI), in the model space's order; `None` if the
    /// normal matrix is singular in that direction.
    pub half_width_95: Vec<Option<f64>>,
    /// Correlation matrix (rows in the model space's order).
    pub correlation: Vec<Vec<f64>>,
    /// Recorded points `n` and constants `p`.
    pub points: usize,
    /// Reduced chi-square `r.r / (n - p)`.
    pub reduced_chi_square: f64,
    /// Pairs `(i, j, rho)` with `|rho| >= IDENTIFIABLE_CORRELATION`.
    pub correlated_pairs: Vec<(usize, usize, f64)>,
    /// Variance inflation factor of each constant (`None` where undetermined).
    #[serde(default)]
    pub inflation: Vec<Option<f64>>,
}

/// The predictions at every recorded point of each experiment of `experiments` at `values`
/// (`None` for a campaign experiment not in the list).
fn predictions(
    campaign: &Campaign,
    space: &ModelSpace,
    values: &[f64],
    experiments: &[usize],
    settings: &SolverSettings,
) -> Result<Vec<Option<Vec<f64>>>, String> {
    let (_, material) = space.material(&campaign.base, values)?;
    let setup = space.setup_values(values);
    let mut out = vec![None; campaign.experiments.len()];
    for &e in experiments {
        let experiment = super::space::with_setup(&campaign.experiments[e], &setup)?;
        let outcome = experiment
            .simulate(&material, settings)
            .map_err(|error| format!("{}: {error}", experiment.file.name))?;
        if !outcome.predicted.iter().all(|p| p.is_finite()) {
            return Err(format!(
                "{}: a prediction is not finite",
                experiment.file.name
            ));
        }
        out[e] = Some(outcome.predicted);
    }
    Ok(out)
}

/// The predictions of a model about its selected constants and their forward-difference
/// slopes (step [`STEP`] of each constant's search range, towards the inside of the range):
/// what the linearised intervals and the posterior's surrogate ([`super::posterior`]) are
/// built from.
#[derive(Clone, Debug)]
pub struct Linearisation {
    /// The selected constants.
    pub values: Vec<f64>,
    /// Predictions at every recorded point, per campaign experiment (`None`: not simulated).
    pub predictions: Vec<Option<Vec<f64>>>,
    /// `d prediction / d constant` at every recorded point, per campaign experiment:
    /// `[point][constant]`.
    pub slopes: Vec<Option<Vec<Vec<f64>>>>,
}

impl Linearisation {
    /// The weighted residuals `r_k = sqrt(w_e) (y_k - m_k) / sigma_k` of `experiments` and
    /// their Jacobian `dr/dtheta` (rows in the same order).
    pub fn residuals(
        &self,
        campaign: &Campaign,
        experiments: &[usize],
    ) -> Result<(Vec<f64>, Vec<Vec<f64>>), String> {
        let (mut residuals, mut jacobian) = (Vec::new(), Vec::new());
        for &e in experiments {
            let (Some(predicted), Some(slopes)) = (&self.predictions[e], &self.slopes[e]) else {
                return Err(format!("experiment {e} was not linearised"));
            };
            let weight = libm::sqrt(campaign.file.experiments[e].weight);
            for ((point, m), slope) in campaign.experiments[e]
                .recording
                .iter()
                .zip(predicted)
                .zip(slopes)
            {
                let scale = weight / point.uncertainty;
                residuals.push(scale * (point.value - m));
                jacobian.push(slope.iter().map(|d| -scale * d).collect());
            }
        }
        Ok((residuals, jacobian))
    }
}

/// Linearise `values` (the selected constants of `space`) on `experiments`: `p + 1`
/// simulations of each, in parallel; the result does not depend on the thread count.
pub fn linearise(
    campaign: &Campaign,
    space: &ModelSpace,
    values: &[f64],
    experiments: &[usize],
) -> Result<Linearisation, String> {
    let p = values.len();
    let settings = SolverSettings {
        threads: Some(1),
        ..SolverSettings::default()
    };
    let steps: Vec<f64> = (0..p)
        .map(|i| STEP * (space.upper[i] - space.lower[i]))
        .collect();
    // Step towards the inside of the range, so that a constant at its bound stays in it.
    let points: Vec<Vec<f64>> = std::iter::once(values.to_vec())
        .chain((0..p).map(|i| {
            let mut shifted = values.to_vec();
            let h = if values[i] + steps[i] <= space.upper[i] {
                steps[i]
            } else {
                -steps[i]
            };
            shifted[i] += h;
            shifted
        }))
        .collect();
    let runs: Vec<Result<Vec<Option<Vec<f64>>>, String>> = points
        .par_iter()
        .map(|point| predictions(campaign, space, point, experiments, &settings))
        .collect();
    let mut runs = runs.into_iter();
    let base = runs.next().ok_or("no evaluation")??;
    let mut slopes: Vec<Option<Vec<Vec<f64>>>> = base
        .iter()
        .map(|p| p.as_ref().map(|p| vec![vec![0.0; values.len()]; p.len()]))
        .collect();
    for (i, run) in runs.enumerate() {
        let shifted = run?;
        let h = points[i + 1][i] - values[i];
        for (e, (at, moved)) in base.iter().zip(&shifted).enumerate() {
            if let (Some(at), Some(moved), Some(slope)) = (at, moved, &mut slopes[e]) {
                for (k, row) in slope.iter_mut().enumerate() {
                    row[i] = (moved[k] - at[k]) / h;
                }
            }
        }
    }
    Ok(Linearisation {
        values: values.to_vec(),
        predictions: base,
        slopes,
    })
}

/// The uncertainty of `values` (the selected constants of `space`) from the recordings of
/// `experiments` (the fitted ones): [`linearise`] then [`from_linearisation`].
pub fn linearised(
    campaign: &Campaign,
    space: &ModelSpace,
    values: &[f64],
    experiments: &[usize],
) -> Result<Uncertainty, String> {
    from_linearisation(
        campaign,
        &linearise(campaign, space, values, experiments)?,
        experiments,
    )
}

/// The uncertainty of the linearised constants from the recordings of `experiments` (the
/// fitted ones, which `linearisation` must cover).
pub fn from_linearisation(
    campaign: &Campaign,
    linearisation: &Linearisation,
    experiments: &[usize],
) -> Result<Uncertainty, String> {
    let p = linearisation.values.len();
    let (base, jacobian) = linearisation.residuals(campaign, experiments)?;
    let n = base.len();
    if n <= p {
        return Err(format!(
            "{n} recorded points for {p} constants: no degrees of freedom left"
        ));
    }
    let chi_square: f64 = base.iter().map(|r| r * r).sum();
    let reduced_chi_square = chi_square / (n - p) as f64;
    // Normal matrix in scaled variables (each column by its norm), for conditioning.
    let norms: Vec<f64> = (0..p)
        .map(|i| libm::sqrt(jacobian.iter().map(|row| row[i] * row[i]).sum::<f64>()))
        .collect();
    let mut normal = vec![vec![0.0; p]; p];
    for row in &jacobian {
        for a in 0..p {
            for b in 0..p {
                if norms[a] > 0.0 && norms[b] > 0.0 {
                    normal[a][b] += row[a] / norms[a] * row[b] / norms[b];
                }
            }
        }
    }
    let inverse = invert(&normal);
    let mut half_width_95 = vec![None; p];
    let mut correlation = vec![vec![0.0; p]; p];
    let mut correlated_pairs = Vec::new();
    let mut inflation = vec![None; p];
    if let Some(inverse) = &inverse {
        for a in 0..p {
            if normal[a][a] > 0.0 {
                inflation[a] = Some(normal[a][a] * inverse[a][a]);
            }
        }
        for a in 0..p {
            if norms[a] > 0.0 && inverse[a][a] > 0.0 {
                half_width_95[a] =
                    Some(1.96 * libm::sqrt(reduced_chi_square * inverse[a][a]) / norms[a]);
            }
            for b in 0..p {
                let scale = libm::sqrt(inverse[a][a] * inverse[b][b]);
                correlation[a][b] = if scale > 0.0 {
                    inverse[a][b] / scale
                } else {
                    0.0
                };
            }
        }
        for (a, row) in correlation.iter().enumerate() {
            for (b, rho) in row.iter().enumerate().skip(a + 1) {
                if rho.abs() >= IDENTIFIABLE_CORRELATION {
                    correlated_pairs.push((a, b, *rho));
                }
            }
        }
    }
    Ok(Uncertainty {
        inflation,
        half_width_95,
        correlation,
        points: n,
        reduced_chi_square,
        correlated_pairs,
    })
}

/// Inverse of a symmetric positive semi-definite matrix by Gauss-Jordan elimination with
/// partial pivoting; `None` if a pivot falls below 1e-12 of the largest diagonal entry
/// (singular: some combination of constants is not determined at all).
pub(super) fn invert(matrix: &[Vec<f64>]) -> Option<Vec<Vec<f64>>> {
    let n = matrix.len();
    let largest = (0..n).map(|i| matrix[i][i].abs()).fold(0.0, f64::max);
    let mut a: Vec<Vec<f64>> = matrix.to_vec();
    let mut inverse: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|j| if i == j { 1.0 } else { 0.0 }).collect())
        .collect();
    for column in 0..n {
        let pivot =
            (column..n).max_by(|&x, &y| a[x][column].abs().total_cmp(&a[y][column].abs()))?;
        if a[pivot][column].abs() <= 1e-12 * largest {
            return None;
        }
        a.swap(column, pivot);
        inverse.swap(column, pivot);
        let scale = a[column][column];
        for j in 0..n {
            a[column][j] /= scale;
            inverse[column][j] /= scale;
        }
        for row in 0..n {
            if row != column {
                let factor = a[row][column];
                for j in 0..n {
                    a[row][j] -= factor * a[column][j];
                    inverse[row][j] -= factor * inverse[column][j];
                }
            }
        }
    }
    Some(inverse)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_inverse_of_a_known_matrix_and_a_singular_one() {
        // GOAL: the normal-matrix inverse is right and singularity is detected.
        // SETUP: [[4, 2], [2, 3]] and [[1, 1], [1, 1]].
        // REFERENCE: [[3, -2], [-2, 4]] / 8; None.
        let inverse = invert(&[vec![4.0, 2.0], vec![2.0, 3.0]]).unwrap();
        let expected = [[0.375, -0.25], [-0.25, 0.5]];
        for a in 0..2 {
            for b in 0..2 {
                assert!((inverse[a][b] - expected[a][b]).abs() < 1e-15);
            }
        }
        assert!(invert(&[vec![1.0, 1.0], vec![1.0, 1.0]]).is_none());
    }
}
