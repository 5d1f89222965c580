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
//! other constants re-tuned. Under the null (the term is not needed, residuals are the recorded
//! noise) `S ~ chi2(1)`. It is divided by `s^2 = max(1, (r'Mr - S)/(n - p - 1))`, so that a
//! recorded uncertainty that is too small does not inflate every term alike. For a term
//! bounded at its null (heating, upturn, saturation, friction...) the statistic counts only if
//! the first-order estimate `gamma* = -(j'Mr)/(j'Mj)` lies on the physical side, and the
//! p-value is the chi-bar-square `P(chi2(1) > S)/2` (Self & Liang 1987). p-values are
//! Bonferroni-corrected over the library.

use super::candidates::Candidate;
use super::engine::Engine;
use super::fit::{residuals_at, Fit};
use super::stats::{chi_square_upper_tail, dot, project_out};
use super::DiagnoseError;
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
    /// The score statistic after scaling, `S / s^2`.
    pub statistic: f64,
    /// The unscaled statistic `S`.
    pub raw_statistic: f64,
    /// The noise scale `s^2`.
    pub scale: f64,
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
    let projected_residuals = project_out(&fit.jacobian, &fit.residuals);
    let residual_misfit = dot(&projected_residuals, &projected_residuals);
    let count = library.len().max(1) as f64;
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
            single_p_value: 1.0,
            p_value: 1.0,
            significant: false,
            share: 0.0,
            estimate: candidate.null,
            note: None,
        };
        let stepped = match stepped {
            Ok(r) => r,
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
        let projection = dot(&projected_column, &fit.residuals);
        let raw = projection * projection / information;
        let estimate_unit = -projection / information;
        let dof = n as f64 - p as f64 - 1.0;
        let scale = if dof > 0.0 {
            ((residual_misfit - raw) / dof).max(1.0)
        } else {
            1.0
        };
        let statistic = raw / scale;
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
        test.p_value = (single * count).min(1.0);
        test.significant = test.p_value < alpha;
        test.share = if residual_misfit > 0.0 {
            (raw / residual_misfit).min(1.0)
        } else {
            0.0
        };
        test.estimate = candidate.parameter.from_unit(null_unit + estimate_unit);
        tests.push(test);
    }
    Ok(tests)
}
