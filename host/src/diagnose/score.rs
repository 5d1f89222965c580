//! The Lagrange-multiplier (score) test of each candidate term at its null value (Rao 1948;
//! in regression form, e.g. Engle 1984, Handbook of Econometrics II ch. 13).
//!
//! With `r` the whitened residuals of the fitted experiments at the least-squares fit of the
//! current model, `J` their Jacobian with respect to the fitted constants and `j` the
//! derivative with respect to the new term's constant at its null (forward difference, one
//! simulation), the residual-maker `M = I - J (J'J)^-1 J'` removes what re-tuning the current
//! constants can do, and
//!
//! ```text
//! S = (j' M r)^2 / (j' M j)
//! ```
//!
//! is the drop of the residual sum of squares that the term buys to first order, with the
//! other constants re-tuned. Under the null with independent residuals of the recorded size,
//! `S ~ chi2(1)`.
//!
//! **Correlated residuals.** A model that misses something leaves residuals that are smooth
//! along each recording (lag-1 autocorrelation ~0.9 is common), and then `S` overstates the
//! evidence many times over: a smooth column finds a large projection on smooth residuals by
//! chance. The statistic used is therefore `T = (z'r)^2 / Var(z'r)`, `z = M j`, with the
//! variance from a noise model per recording: a first-order autoregression
//! ([`Ar1`](super::stats::Ar1)) whose variance and lag-1 correlation are estimated from
//! what the term leaves, `e = M r + gamma* z` (after its first-order fit), along the recording,
//! with the variance floored at the recorded uncertainty and inflated by `n / (n - p - 1)`.
//! The term is thus credited only as far as what remains after it looks like independent
//! noise: the right term leaves white residuals and keeps its statistic; a wrong one leaves
//! the structure, whose correlation inflates the variance. With uncorrelated residuals `T`
//! is `S / s^2` (`s^2` the mean square of `e`, at least 1). The calibration of `T` under
//! AR(1) noise is a unit test (`stats`, 3 % rejections at the 5 % level where `S / s^2`
//! rejects 64 %). A term whose full range moves the fit by less than the noise (`j'Mj < 1`,
//! in recorded uncertainties) is reported "not identifiable here" and not ranked. For a term
//! bounded at its null (heating, upturn, saturation, friction...) the statistic counts only if
//! the first-order estimate `gamma* = -(j'Mr)/(j'Mj)` lies on the physical side, and the
//! p-value is the chi-bar-square `P(chi2(1) > S)/2` (Self & Liang 1987). A term tried over a
//! grid of a shape constant (the heating transition's window) keeps its best variant, whose
//! p-value is multiplied by the grid's size; p-values are then Bonferroni-corrected over the
//! terms.

use super::candidates::Candidate;
use super::stats::{chi_square_upper_tail, Ar1};
use super::DiagnoseError;
use crate::fit::least_squares::{residuals_at, Fit};
use crate::fit::linear::{dot, project_out};
use crate::fit::Engine;
use serde::{Deserialize, Serialize};

/// The score test of one candidate.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ScoreTest {
    /// Term name.
    pub name: String,
    /// What it adds.
    pub physics: String,
    /// Its constant.
    pub parameter: String,
    /// The statistic `T = (z'r)^2 / Var(z'r)` under the per-recording AR(1) noise model.
    pub statistic: f64,
    /// The unscaled statistic `S` (independent residuals of the recorded size).
    pub raw_statistic: f64,
    /// `S / T`: how much the noise model widens the statistic's variance over the recorded
    /// uncertainty's (1 for independent residuals at the recorded size).
    pub scale: f64,
    /// Largest lag-1 correlation of what the term leaves, over the recordings.
    #[serde(default)]
    pub residual_correlation: f64,
    /// p-value of the single test.
    pub single_p_value: f64,
    /// Bonferroni-corrected p-value (ranking key).
    pub p_value: f64,
    /// Significant at the family-wise level.
    pub significant: bool,
    /// Share of the misfit `r'Mr` the term removes to first order, `S / r'Mr`.
    pub share: f64,
    /// First-order estimate of the term's constant, `gamma*` (SI).
    pub estimate: f64,
    /// Why the test could not speak, if it could not.
    pub note: Option<String>,
}

/// Score tests of every candidate at the current model's fit `fit` over `fitted`.
pub fn score_tests(
    engine: &mut Engine,
    library: &[Candidate],
    fit: &Fit,
    fitted: &[usize],
    alpha: f64,
) -> Result<Vec<ScoreTest>, DiagnoseError> {
    let n = fit.residuals.len();
    let p = fit.values.len();
    let ranges = super::row_ranges(engine.experiments, fitted);
    let dof = n as f64 - p as f64 - 1.0;
    let inflation = if dof > 0.0 { n as f64 / dof } else { 1.0 };
    let projected_residuals = project_out(&fit.jacobian, &fit.residuals);
    let residual_misfit = dot(&projected_residuals, &projected_residuals);
    let mut groups: Vec<&str> = Vec::new();
    for candidate in library {
        if !groups.contains(&candidate.group.as_str()) {
            groups.push(&candidate.group);
        }
    }
    let count = groups.len().max(1) as f64;
    let mut tests = Vec::with_capacity(library.len());
    for candidate in library {
        let range = candidate.parameter.upper - candidate.parameter.lower;
        let step_unit = candidate.step / range;
        let null_unit = candidate.parameter.to_unit(candidate.null);
        let mut unit: Vec<f64> = fit.unit.clone();
        unit.push(null_unit + step_unit);
        let stepped = residuals_at(engine, &candidate.extended, &[unit], fitted)?.remove(0);
        let mut test = ScoreTest {
            name: candidate.name.clone(),
            physics: candidate.physics.clone(),
            parameter: candidate.parameter.name.clone(),
            statistic: 0.0,
            raw_statistic: 0.0,
            scale: 1.0,
            residual_correlation: 0.0,
            single_p_value: 1.0,
            p_value: 1.0,
            significant: false,
            share: 0.0,
            estimate: candidate.null,
            note: None,
        };
        let stepped = match stepped {
            Ok(r) => r,
            // A stop request is not a failed step.
            Err(_) if crate::fit::interrupt::requested() => {
                return Err(crate::fit::interrupt::Interrupted.into());
            }
            Err(error) => {
                test.note = Some(format!("the simulation a small step away failed: {error}"));
                tests.push(test);
                continue;
            }
        };
        let column: Vec<f64> = stepped
            .iter()
            .zip(&fit.residuals)
            .map(|(a, b)| (a - b) / step_unit)
            .collect();
        let projected_column = project_out(&fit.jacobian, &column);
        let information = dot(&projected_column, &projected_column);
        let energy = dot(&column, &column);
        if energy == 0.0 {
            test.note = Some("no effect on the recorded measurements".into());
            tests.push(test);
            continue;
        }
        if information <= 1e-6 * energy {
            test.note =
                Some("its effect is indistinguishable from re-tuning the fitted constants".into());
            tests.push(test);
            continue;
        }
        if information < 1.0 {
            test.note = Some(
                "not identifiable here: over its whole range it moves the fit by less than the \
                 recorded uncertainty"
                    .into(),
            );
            tests.push(test);
            continue;
        }
        let projection = dot(&projected_column, &fit.residuals);
        let raw = projection * projection / information;
        let estimate_unit = -projection / information;
        // What the term leaves, e = M r + gamma* z, per recording: its noise model.
        let mut variance = 0.0;
        for range in &ranges {
            let left: Vec<f64> = range
                .clone()
                .map(|i| projected_residuals[i] + estimate_unit * projected_column[i])
                .collect();
            let model = Ar1::estimate(&left, inflation);
            test.residual_correlation = test.residual_correlation.max(model.correlation);
            variance += model.variance_of_sum(&projected_column[range.clone()]);
        }
        let statistic = if variance > 0.0 {
            projection * projection / variance
        } else {
            0.0
        };
        let scale = if statistic > 0.0 {
            raw / statistic
        } else {
            1.0
        };
        let admissible = !candidate.one_sided || estimate_unit * step_unit.signum() > 0.0;
        let single = if !admissible {
            test.note = Some("the recordings ask for the term on its unphysical side".into());
            1.0
        } else if candidate.one_sided {
            0.5 * chi_square_upper_tail(statistic, 1.0)
        } else {
            chi_square_upper_tail(statistic, 1.0)
        };
        test.statistic = if admissible { statistic } else { 0.0 };
        test.raw_statistic = raw;
        test.scale = scale;
        test.single_p_value = single;
        test.share = if residual_misfit > 0.0 {
            (raw / residual_misfit).min(1.0)
        } else {
            0.0
        };
        test.estimate = candidate.parameter.from_unit(null_unit + estimate_unit);
        // The label follows the side of the null the recordings ask for.
        if let Some(below) = &candidate.physics_below {
            if estimate_unit < 0.0 {
                test.physics = below.clone();
            }
        }
        tests.push(test);
    }
    Ok(best_per_group(library, &tests, &groups, count, alpha))
}

/// One test per term: of a group of variants over a grid of a shape constant, the one with the
/// largest statistic, its p-value multiplied by the group's size (Bonferroni over the grid);
/// then Bonferroni over the `count` terms.
fn best_per_group(
    library: &[Candidate],
    tests: &[ScoreTest],
    groups: &[&str],
    count: f64,
    alpha: f64,
) -> Vec<ScoreTest> {
    let mut kept = Vec::with_capacity(groups.len());
    for group in groups {
        let members: Vec<usize> = library
            .iter()
            .enumerate()
            .filter(|(_, c)| c.group == *group)
            .map(|(i, _)| i)
            .collect();
        let best = members
            .iter()
            .copied()
            .reduce(|a, b| {
                if tests[b].statistic > tests[a].statistic {
                    b
                } else {
                    a
                }
            })
            .unwrap_or(members[0]);
        let mut test = tests[best].clone();
        if members.len() > 1 {
            test.single_p_value = (test.single_p_value * members.len() as f64).min(1.0);
            let grid = format!("the best of {} variants of {group}", members.len());
            test.note = Some(match test.note {
                Some(note) => format!("{grid}; {note}"),
                None => grid,
            });
        }
        test.p_value = (test.single_p_value * count).min(1.0);
        test.significant = test.p_value < alpha;
        kept.push(test);
    }
    kept
}
