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
use serde::{Deserialize, Serialize};

/// Correlation above which two constants are reported as not separately identifiable.
pub const IDENTIFIABLE_CORRELATION: f64 = 0.95;

/// Variance inflation factor above which a constant is reported as determined only in
/// combination with others.
pub const COLLINEAR_VIF: f64 = 10.0;

/// Forward-difference step, as a fraction of each constant's search range.
const STEP: f64 = 1.0e-3;

/// The linearisation is contradicted where it predicts at least this many times the misfit
/// increase a logged candidate scored: its intervals are then too narrow by about the square
/// root (a factor 2 or more) in that direction.
pub const CONTRADICTED_RATIO: f64 = 4.0;

/// The chi-square increase of a two-sided 95 % likelihood-ratio interval of one constant.
const CHI_SQUARE_95: f64 = 3.84;

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
    /// Whether the search's own candidates bear the linearisation out ([`search_check`]);
    /// `None` if no logged candidate could be compared.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub search_check: Option<SearchCheck>,
}

/// The linearisation held against the candidates the search logged. The intervals assume a
/// misfit quadratic from the forward-difference step (1e-3 of each range) out to their own
/// width; an objective that is kinked or noisy on that scale (a ballistic limit's exits,
/// where a shot near the limit changes from stop to perforation) breaks it, and the search's
/// candidates show it for free: a candidate that scored as well as the selected constants,
/// but that the linearisation places outside its 95 % region, proves the region too small.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SearchCheck {
    /// Logged candidates compared (simulated on every fitted experiment, on the files'
    /// meshes).
    pub compared: usize,
    /// The candidate reported (SI, the model space's order): of the good candidates (within
    /// `threshold`) that contradict the linearisation, the one it places furthest out;
    /// without a contradiction, the nearest in its metric `dtheta^T J^T J dtheta`.
    pub candidate: Vec<f64>,
    /// The chi-square increase over the selected constants the linearisation predicts at
    /// `candidate`, `|r_0 + J dtheta|^2 - |r_0|^2`.
    pub predicted: f64,
    /// The chi-square increase `candidate` scored.
    pub scored: f64,
    /// The increase within which a candidate is as good as the selected one at 95 %:
    /// `3.84 max(s^2, 1)` (the recorded uncertainties, or wider if the fit misses them).
    pub threshold: f64,
    /// Logged candidates within `threshold` of the selected one (itself included).
    pub within: usize,
    /// The smallest and largest value of each constant among those (SI).
    pub span: Vec<(f64, f64)>,
    /// A good candidate lies outside the linearisation's 95 % region (predicted above
    /// `threshold`) and scored under `1 / CONTRADICTED_RATIO` of its prediction: the
    /// intervals are too narrow.
    pub too_narrow: bool,
}

/// Hold the linearisation (weighted residuals `residuals` at the selected constants
/// `selected`, Jacobian `jacobian`, reduced chi-square `reduced_chi_square`) against the
/// logged candidates `logged` (`(constants, chi-square)`, the chi-square weighted as the
/// residuals are; `selected_chi_square` the selected constants' own); `None` if none differs
/// from the selected constants.
pub fn search_check(
    residuals: &[f64],
    jacobian: &[Vec<f64>],
    reduced_chi_square: f64,
    selected: &[f64],
    selected_chi_square: f64,
    logged: &[(Vec<f64>, f64)],
) -> Option<SearchCheck> {
    let base: f64 = residuals.iter().map(|r| r * r).sum();
    let threshold = CHI_SQUARE_95 * reduced_chi_square.max(1.0);
    // (candidate, J dtheta . J dtheta, predicted increase, scored increase)
    let compared: Vec<(&[f64], f64, f64, f64)> = logged
        .iter()
        .filter(|(values, chi)| {
            chi.is_finite() && values.len() == selected.len() && values.as_slice() != selected
        })
        .map(|(values, chi)| {
            let delta: Vec<f64> = values.iter().zip(selected).map(|(v, s)| v - s).collect();
            let moved: Vec<f64> = jacobian
                .iter()
                .map(|row| row.iter().zip(&delta).map(|(j, d)| j * d).sum())
                .collect();
            let metric = moved.iter().map(|x| x * x).sum();
            let predicted = residuals
                .iter()
                .zip(&moved)
                .map(|(r, d)| (r + d) * (r + d))
                .sum::<f64>()
                - base;
            (
                values.as_slice(),
                metric,
                predicted,
                chi - selected_chi_square,
            )
        })
        .collect();
    let good = |c: &&(&[f64], f64, f64, f64)| c.3 <= threshold;
    let contradicts = |c: &&(&[f64], f64, f64, f64)| {
        good(c) && c.2 > threshold && c.2 > CONTRADICTED_RATIO * c.3.max(0.0)
    };
    let contradicting = compared
        .iter()
        .filter(contradicts)
        .max_by(|a, b| a.2.total_cmp(&b.2));
    let reported = match contradicting {
        Some(candidate) => candidate,
        None => compared.iter().min_by(|a, b| a.1.total_cmp(&b.1))?,
    };
    let good: Vec<&[f64]> = std::iter::once(selected)
        .chain(compared.iter().filter(good).map(|c| c.0))
        .collect();
    let span = (0..selected.len())
        .map(|i| {
            good.iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                    (lo.min(v[i]), hi.max(v[i]))
                })
        })
        .collect();
    Some(SearchCheck {
        compared: compared.len(),
        candidate: reported.0.to_vec(),
        predicted: reported.2,
        scored: reported.3,
        threshold,
        within: good.len(),
        span,
        too_narrow: contradicting.is_some(),
    })
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
    /// The linearisation from the predictions at each of `points` ([`difference_points`]:
    /// the selected constants, then one step per constant) on `experiments`; `predicted(i,
    /// e)` gives point `i`'s predictions on the `e`-th of `experiments`. The first failed
    /// simulation, in point and then experiment order, is the error.
    pub fn assemble(
        campaign: &Campaign,
        points: &[Vec<f64>],
        experiments: &[usize],
        predicted: impl Fn(usize, usize) -> Result<Vec<f64>, String>,
    ) -> Result<Self, String> {
        let values = points.first().ok_or("no evaluation")?;
        let at_point = |i: usize| -> Result<Vec<Option<Vec<f64>>>, String> {
            let mut out = vec![None; campaign.experiments.len()];
            for (e, &experiment) in experiments.iter().enumerate() {
                out[experiment] = Some(predicted(i, e)?);
            }
            Ok(out)
        };
        let base = at_point(0)?;
        let mut slopes: Vec<Option<Vec<Vec<f64>>>> = base
            .iter()
            .map(|p| p.as_ref().map(|p| vec![vec![0.0; values.len()]; p.len()]))
            .collect();
        for (i, point) in points.iter().enumerate().skip(1) {
            let shifted = at_point(i)?;
            let constant = i - 1;
            let h = point[constant] - values[constant];
            for (e, (at, moved)) in base.iter().zip(&shifted).enumerate() {
                if let (Some(at), Some(moved), Some(slope)) = (at, moved, &mut slopes[e]) {
                    for (k, row) in slope.iter_mut().enumerate() {
                        row[constant] = (moved[k] - at[k]) / h;
                    }
                }
            }
        }
        Ok(Self {
            values: values.clone(),
            predictions: base,
            slopes,
        })
    }

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

/// The points of the forward differences about `values`: `values` itself, then each constant
/// stepped by [`STEP`] of its search range, towards the inside of the range (so that a
/// constant at its bound stays in it).
pub fn difference_points(space: &ModelSpace, values: &[f64]) -> Vec<Vec<f64>> {
    std::iter::once(values.to_vec())
        .chain((0..values.len()).map(|i| {
            let step = STEP * (space.upper[i] - space.lower[i]);
            let mut shifted = values.to_vec();
            shifted[i] += if values[i] + step <= space.upper[i] {
                step
            } else {
                -step
            };
            shifted
        }))
        .collect()
}

/// The predictions of `outcome`, the simulation of `experiment`, if every one is finite.
pub fn finite_predictions(
    campaign: &Campaign,
    experiment: usize,
    outcome: &crate::experiment::Outcome,
) -> Result<Vec<f64>, String> {
    if outcome.predicted.iter().all(|p| p.is_finite()) {
        Ok(outcome.predicted.clone())
    } else {
        Err(format!(
            "{}: a prediction is not finite",
            campaign.experiments[experiment].file.name
        ))
    }
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
        search_check: None,
        inflation,
        half_width_95,
        correlation,
        points: n,
        reduced_chi_square,
        correlated_pairs,
    })
}

/// The chi-square of `evaluation` over `experiments`, each experiment's points weighted as
/// [`Linearisation::residuals`] weights them (`sum w_e n_e chi_e^2`); `None` if a score is
/// missing.
fn weighted_chi_square(
    campaign: &Campaign,
    evaluation: &super::Evaluation,
    experiments: &[usize],
) -> Option<f64> {
    experiments.iter().try_fold(0.0, |sum, &e| {
        let score = evaluation.scores.get(e).copied().flatten()?;
        let n = campaign.experiments.get(e)?.recording.len() as f64;
        Some(sum + campaign.file.experiments[e].weight * n * score.chi * score.chi)
    })
}

/// [`search_check`] of `uncertainty` (from `linearisation` of the `selected` evaluation on
/// `experiments`) against the model's logged candidates `seen` that were simulated on every
/// one of `experiments` on the files' meshes.
pub fn against_search(
    campaign: &Campaign,
    linearisation: &Linearisation,
    uncertainty: &Uncertainty,
    selected: &super::Evaluation,
    seen: &[super::Evaluation],
    experiments: &[usize],
) -> Option<SearchCheck> {
    let (residuals, jacobian) = linearisation.residuals(campaign, experiments).ok()?;
    let selected_chi_square = weighted_chi_square(campaign, selected, experiments)?;
    let logged: Vec<(Vec<f64>, f64)> = seen
        .iter()
        .filter(|e| matches!(e.status, super::Status::Ok) && e.fidelity.is_fine() && !e.corrected)
        .filter_map(|e| {
            Some((
                e.values.clone(),
                weighted_chi_square(campaign, e, experiments)?,
            ))
        })
        .collect();
    search_check(
        &residuals,
        &jacobian,
        uncertainty.reduced_chi_square,
        &linearisation.values,
        selected_chi_square,
        &logged,
    )
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

    /// Weighted residuals `r_k = (y_k - m_k(theta)) / sigma` of a model `m_k = theta x_k`
    /// against data `y_k = 2 x_k + e_k`, and their chi-square.
    fn line(theta: f64) -> (Vec<f64>, f64) {
        let (x, noise) = ([1.0, 2.0, 3.0, 4.0], [0.3, -0.2, 0.1, -0.15]);
        let r: Vec<f64> = x
            .iter()
            .zip(noise)
            .map(|(x, e)| (2.0 * x + e - theta * x) / 0.5)
            .collect();
        let chi = r.iter().map(|r| r * r).sum();
        (r, chi)
    }

    #[test]
    fn the_search_bears_out_a_quadratic_misfit_and_contradicts_a_kinked_one() {
        // GOAL: the check leaves intervals alone where the misfit is quadratic, and flags
        // them as too narrow where the slope over the forward-difference step overstates
        // the misfit a nearby, equally good candidate scored.
        // SETUP: a straight-line model (its misfit is exactly quadratic in theta), selected
        // at theta 2, Jacobian -x/sigma; logged candidates at 1.95, 2.2 and 3 scored exactly.
        // Then the same residuals with the Jacobian a jump would give over a 1e-3 step
        // (slope 50 times the true one), the candidates scored as before.
        // REFERENCE: exact quadratic: predicted = scored at every candidate; kinked: at the
        // nearest (1.95) predicted 2500 times the true increase.
        let (r0, chi0) = line(2.0);
        let jacobian: Vec<Vec<f64>> = [1.0, 2.0, 3.0, 4.0]
            .iter()
            .map(|x| vec![-x / 0.5])
            .collect();
        let logged: Vec<(Vec<f64>, f64)> = [1.95, 2.2, 3.0]
            .iter()
            .map(|&t| (vec![t], line(t).1))
            .collect();
        let check = search_check(&r0, &jacobian, 1.0, &[2.0], chi0, &logged).unwrap();
        assert_eq!(check.compared, 3);
        assert_eq!(check.candidate, vec![1.95]);
        assert!((check.predicted - check.scored).abs() < 1e-9 * check.scored.abs().max(1.0));
        assert!(!check.too_narrow);
        let kinked: Vec<Vec<f64>> = jacobian.iter().map(|row| vec![50.0 * row[0]]).collect();
        let check = search_check(&r0, &kinked, 1.0, &[2.0], chi0, &logged).unwrap();
        assert_eq!(check.candidate, vec![1.95]);
        assert!(check.scored <= check.threshold, "{check:?}");
        assert!(check.predicted > 100.0 * check.scored, "{check:?}");
        assert!(check.too_narrow);
        // The span covers the selected constant and the good candidates, not the poor one.
        assert!(
            check.span[0].0 <= 1.95 && check.span[0].1 < 3.0,
            "{check:?}"
        );
        // A candidate far worse than the threshold is no evidence, however far off the
        // prediction: only the poor candidate logged.
        let poor = [(vec![3.0], line(3.0).1)];
        let check = search_check(&r0, &kinked, 1.0, &[2.0], chi0, &poor).unwrap();
        assert!(check.scored > check.threshold && !check.too_narrow);
        // Nothing to compare: no check.
        assert!(search_check(&r0, &kinked, 1.0, &[2.0], chi0, &[(vec![2.0], chi0)]).is_none());
    }
}
