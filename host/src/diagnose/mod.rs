//! `stoss diagnose`: after a calibration, locate where the model misses the recordings, name
//! the physics it left out, add it, refit, and show whether the fit improves.
//!
//! 1. **Refit the calibrated model by least squares** (chi-square of the whitened residuals,
//!    the Gaussian likelihood the statistics below need), starting from the calibration's
//!    selected constants: the "before" model.
//! 2. **Locate** ([`locate`]): per experiment, chi-square against the recorded uncertainty, the
//!    runs test and autocorrelation, chi-square per window (Bonferroni), bands related to the
//!    tracked state of the material there.
//! 3. **Attribute** ([`candidates`], [`score`]): a Lagrange-multiplier (score) test for every
//!    nested term of the library, from the Jacobian of the fitted residuals with respect to
//!    the calibrated constants (shared, `p` simulations) and one simulation per term at a
//!    finite step from its null, its variance from an AR(1) noise model per recording. Ranked
//!    by p-value (Bonferroni over the library; one-sided chi-bar-square for terms bounded at
//!    their null).
//! 4. **Refit** ([`crate::fit::least_squares`]): the significant terms in rank order (at most `max_refits`), each
//!    with every constant refitted; a term earns its constant when the Bayesian information
//!    criterion drops and so does the held-out error (approximate leave-one-out over the
//!    fitted experiments plus the campaign's held-out experiments); of those that do, the one
//!    with the lowest BIC is accepted (a later-ranked term needs a BIC lower by
//!    [`POSITIVE_EVIDENCE`]). When none is, the best-ranked terms the score test did not
//!    find significant are refitted as well and need, besides, a significant likelihood
//!    ratio ([`likelihood_ratio`]): the score test is first-order and under-rates terms the
//!    fitted constants re-shape around nonlinearly.
//! 5. **Alternative families** ([`families`]): when the misfit left is still structured, the
//!    strength is replaced by the kernel's other families, each fitted in full; one replaces
//!    the model on strong BIC evidence and a lower held-out error.
//! 6. **Report** ([`report`]): errors per experiment before and after, the misfit binned in
//!    state space ([`state_space`]), overlays, residual figures with the significant bands,
//!    and a plain-language verdict that says when the model still misses.

pub mod candidates;
pub mod families;
pub mod likelihood_ratio;
pub mod localisation;
pub mod locate;
pub mod location;
pub mod numerical;
pub mod report;
pub mod score;
pub mod state_space;
pub mod stats;

use crate::fit::executor::{Executor, Prediction};
use crate::fit::least_squares::{self, levenberg_marquardt, Fit};
use crate::fit::linear;
use crate::fit::result::ModelResult;
pub use crate::fit::Progress;
use crate::fit::{score as error_score, Campaign, Score};
use crate::fit::{Engine, FitError, Hypothesis};
use candidates::{Candidate, NotApplicable};
use locate::ExperimentMisfit;
use location::{LocatedMisfit, LocationCheck};
use score::ScoreTest;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Times a leave-one-out fold's Gauss-Newton step is halved when its experiment cannot be
/// simulated at the stepped constants, before the fold counts as failed.
pub const FOLD_STEP_HALVINGS: usize = 3;

/// BIC drop by which a later-ranked term that earns its constant displaces an accepted one:
/// "positive" evidence on Kass & Raftery's (1995) scale.
pub const POSITIVE_EVIDENCE: f64 = 2.0;

/// Why a diagnosis stopped.
#[derive(Debug, thiserror::Error)]
pub enum DiagnoseError {
    /// Reading or writing a file failed.
    #[error("{0}")]
    Io(String),
    /// The calibration folder is incomplete or inconsistent.
    #[error("calibration: {0}")]
    Calibration(String),
    /// The executor (this machine's pool, Slurm) could not run the simulations.
    #[error("executor: {0}")]
    Executor(String),
    /// A simulation the diagnosis cannot do without failed.
    #[error("simulation failed: {0}")]
    Simulation(String),
    /// Stopped on request (SIGINT, SIGTERM) after the batch in flight was journalled.
    #[error(transparent)]
    Interrupted(#[from] crate::fit::interrupt::Interrupted),
}

impl From<FitError> for DiagnoseError {
    fn from(error: FitError) -> Self {
        match error {
            FitError::Io(e) => Self::Io(e),
            FitError::Executor(e) => Self::Executor(e.to_string()),
            FitError::Simulation(e) => Self::Simulation(e),
            FitError::Interrupted(stop) => Self::Interrupted(stop),
        }
    }
}

/// Settings of a diagnosis.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Options {
    /// Family-wise significance level of the tests.
    pub alpha: f64,
    /// Simulations at once.
    pub parallel: usize,
    /// Levenberg-Marquardt iterations per refit.
    pub iterations: usize,
    /// Terms refitted at most, in rank order: the significant ones; when none of them is
    /// accepted, as many of the others, judged by their likelihood ratio as well.
    pub max_refits: usize,
    /// Rounds at most: after a term is accepted and refitted, the search starts again from
    /// the extended model, until no term earns its place or this many were accepted.
    #[serde(default = "default_max_rounds")]
    pub max_rounds: usize,
}

/// The default [`Options::max_rounds`]: more concealed effects than the recordings of a
/// campaign can tell apart.
fn default_max_rounds() -> usize {
    4
}

impl Default for Options {
    fn default() -> Self {
        Self {
            alpha: 0.01,
            parallel: std::thread::available_parallelism().map_or(2, usize::from),
            iterations: 8,
            max_refits: 3,
            max_rounds: default_max_rounds(),
        }
    }
}

/// How well a hypothesis fits, on the campaign's measures.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Assessment {
    /// Hypothesis label.
    pub label: String,
    /// Fitted constants (name, value).
    pub constants: Vec<(String, f64)>,
    /// Chi-square of the fitted experiments.
    pub chi_square: f64,
    /// Residuals in it.
    pub residuals: usize,
    /// Constants fitted.
    pub constants_fitted: usize,
    /// Scores of every experiment at the fit (seed 000 error and chi).
    pub scores: Vec<Option<Score>>,
    /// Sum of the seed 000 errors over the fitted experiments.
    pub fit_error: f64,
    /// Held-out error: each fitted experiment predicted by the fit without it (approximate
    /// leave-one-out), plus the campaign's held-out experiments; `None` when there is nothing
    /// to hold out.
    pub held_out_error: Option<f64>,
    /// Akaike information criterion `n ln(RSS/n) + 2k`.
    pub aic: f64,
    /// Bayesian information criterion `n ln(RSS/n) + k ln n`.
    pub bic: f64,
    /// Fitted constants that ended at a bound of their range, described.
    #[serde(default)]
    pub at_bounds: Vec<String>,
}

/// A refit with a candidate term.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Refit {
    /// The term.
    pub candidate: String,
    /// The fit.
    pub assessment: Assessment,
    /// The refitted model.
    pub hypothesis: Hypothesis,
    /// Accepted.
    pub accepted: bool,
    /// Why (not).
    pub reason: String,
    /// Where the refit removed misfit against where it was located (terms only; `None`
    /// when nothing was located or for a family).
    #[serde(default)]
    pub location: Option<LocationCheck>,
    /// It earned its constant on the information criterion and the held-out error, but its
    /// improvement lies mostly outside the located misfit ([`location`]).
    #[serde(default)]
    pub refused_for_location: bool,
}

/// A term accepted in one round of the diagnosis, and what it did to the fit.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Round {
    /// The round (1 for the calibrated model's first search).
    pub round: usize,
    /// The accepted term.
    pub accepted: String,
    /// What physics it adds, in words.
    pub physics: String,
    /// The share of the misfit left at the start of the round that the term's score test
    /// attributes to it (0-1).
    pub explained: f64,
    /// The round's starting model: fit error, held-out error and BIC.
    pub before: (f64, Option<f64>, f64),
    /// The same after the term was added and every constant refitted.
    pub after: (f64, Option<f64>, f64),
}

/// The search of a round after the first (the first round's is [`Diagnosis::tests`] and
/// [`Diagnosis::refits`]), from the model the earlier rounds accepted.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RoundSearch {
    /// The round (2, 3, ...).
    pub round: usize,
    /// Score tests, ranked.
    pub tests: Vec<ScoreTest>,
    /// Refits tried, in rank order.
    pub refits: Vec<Refit>,
}

/// Simulation counts.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Cost {
    /// Points (sets of constants) evaluated per stage.
    pub stages: Vec<(String, usize)>,
    /// Experiment simulations run.
    pub simulated: usize,
    /// Experiment simulations replayed from the log.
    pub replayed: usize,
}

/// The diagnosis.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Diagnosis {
    /// Campaign name.
    pub campaign: String,
    /// Calibrated model diagnosed.
    pub model: String,
    /// Settings.
    pub options: Options,
    /// The calibrated model refitted by least squares.
    pub before: Assessment,
    /// Its misfit, per experiment.
    pub misfit_before: Vec<ExperimentMisfit>,
    /// Its misfit over all fitted recordings, binned by the material state behind each
    /// point; the variable that organises most of it first.
    #[serde(default)]
    pub state_misfit: Vec<state_space::StateMisfit>,
    /// The located experiments simulated another way (mesh refined, the other solver): where
    /// the misfit is the simulation's rather than the material's.
    #[serde(default)]
    pub numerical: Vec<numerical::NumericalCheck>,
    /// Score tests, ranked.
    pub tests: Vec<ScoreTest>,
    /// Library terms that do not apply.
    pub not_applicable: Vec<NotApplicable>,
    /// Refits tried, in rank order.
    pub refits: Vec<Refit>,
    /// The accepted refit's misfit, per experiment.
    pub misfit_after: Option<Vec<ExperimentMisfit>>,
    /// The accepted change: the first round's library term, or an alternative family when
    /// [`Self::replacement`] is set (`None`: no missing physics found). Later rounds' terms
    /// are in [`Self::rounds`].
    pub accepted: Option<String>,
    /// Every accepted term, round by round, with the fit after it.
    #[serde(default)]
    pub rounds: Vec<Round>,
    /// The searches of the rounds after the first, the last one the search that found
    /// nothing more (or stopped at [`Options::max_rounds`]).
    #[serde(default)]
    pub later_rounds: Vec<RoundSearch>,
    /// Non-nested alternatives tried (other strength families, fitted in full), when the
    /// misfit left after the library's terms is still structured.
    #[serde(default)]
    pub alternatives: Vec<Refit>,
    /// The alternative family that replaces the calibrated model's strength, if one won.
    #[serde(default)]
    pub replacement: Option<String>,
    /// The plain-language verdict.
    pub verdict: String,
    /// Simulation cost.
    pub cost: Cost,
}

impl Diagnosis {
    /// The refit the diagnosis ends with: the winning family, else the last round's term
    /// (none: nothing accepted).
    pub fn final_refit(&self) -> Option<&Refit> {
        if let Some(name) = &self.replacement {
            return self.alternatives.iter().find(|r| &r.candidate == name);
        }
        let last = self.rounds.last()?;
        self.refits
            .iter()
            .chain(self.later_rounds.iter().flat_map(|r| &r.refits))
            .filter(|r| r.accepted)
            .find(|r| r.candidate == last.accepted)
    }
}

/// The calibrated model to diagnose from a calibration's results: `model` by name, or the
/// calibration's selected model (`fit::result::selected_model`: held-out prediction where
/// experiments are held out, else the fit, a margin inside the noise decided by the
/// information criterion), or, if no model could be scored on `campaign`, the lowest fit
/// error.
pub fn selected<'r>(
    results: &'r [ModelResult],
    campaign: &crate::fit::Campaign,
    model: Option<&str>,
) -> Result<&'r ModelResult, DiagnoseError> {
    match model {
        Some(name) => results.iter().find(|r| r.model == name).ok_or_else(|| {
            DiagnoseError::Calibration(format!(
                "no model `{name}` in the calibration (it has: {})",
                results
                    .iter()
                    .map(|r| r.model.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        }),
        None => {
            let chosen = crate::fit::result::selected_model_of(results, campaign);
            results
                .iter()
                .find(|r| Some(&r.model) == chosen.as_ref())
                .or_else(|| {
                    results
                        .iter()
                        .min_by(|a, b| a.fit_error.total_cmp(&b.fit_error))
                })
                .ok_or_else(|| DiagnoseError::Calibration("result.json holds no model".into()))
        }
    }
}

/// Row ranges of each fitted experiment in the concatenated residual vector.
pub(super) fn row_ranges(
    all: &[crate::experiment::Experiment],
    experiments: &[usize],
) -> Vec<std::ops::Range<usize>> {
    let mut start = 0;
    experiments
        .iter()
        .map(|&e| {
            let n = all[e].recording.len();
            let range = start..start + n;
            start += n;
            range
        })
        .collect()
}

/// Assess a fit: scores of every experiment, errors, information criteria and the
/// approximate leave-one-out held-out error (one Gauss-Newton step from the full fit without
/// the experiment's rows, then a real simulation of the left-out experiment).
fn assess(
    campaign: &Campaign,
    engine: &mut Engine,
    hypothesis: &Hypothesis,
    fit: &Fit,
    fitted: &[usize],
) -> Result<(Assessment, Vec<Vec<f64>>), DiagnoseError> {
    let all: Vec<usize> = (0..campaign.experiments.len()).collect();
    let predictions = engine
        .predict(hypothesis, std::slice::from_ref(&fit.values), &all)?
        .remove(0)
        .map_err(|e| DiagnoseError::Simulation(format!("{}: {e}", hypothesis.label)))?;
    let scores: Vec<Option<Score>> = campaign
        .experiments
        .iter()
        .zip(&predictions)
        .map(|(e, p)| error_score(&e.recording, p))
        .collect();
    let weight = |i: usize| campaign.file.experiments[i].weight;
    let fit_error: f64 = fitted
        .iter()
        .map(|&i| scores[i].map_or(f64::NAN, |s| s.error) * weight(i))
        .sum();
    // Approximate leave-one-out: one damped Gauss-Newton step per fold from the full fit.
    let ranges = row_ranges(&campaign.experiments, fitted);
    let mut fold_steps: Vec<Vec<f64>> = Vec::new();
    if fitted.len() >= 2 && !fit.unit.is_empty() {
        for range in &ranges {
            let keep = |i: usize| !range.contains(&i);
            let columns: Vec<Vec<f64>> = fit
                .jacobian
                .iter()
                .map(|c| {
                    c.iter()
                        .enumerate()
                        .filter(|(i, _)| keep(*i))
                        .map(|(_, x)| *x)
                        .collect()
                })
                .collect();
            let residuals: Vec<f64> = fit
                .residuals
                .iter()
                .enumerate()
                .filter(|(i, _)| keep(*i))
                .map(|(_, x)| *x)
                .collect();
            let gradient: Vec<f64> = linear::transpose_times(&columns, &residuals)
                .iter()
                .map(|g| -g)
                .collect();
            fold_steps.push(
                linear::solve_damped(&linear::gram(&columns), &gradient, 1e-3)
                    .unwrap_or_else(|| vec![0.0; fit.unit.len()]),
            );
        }
    }
    // A fold whose step lands on constants its experiment cannot be simulated with (a
    // linearised step can leave the region where the model is valid) is tried again with the
    // step halved, at most FOLD_STEP_HALVINGS times; then the fold counts as failed (infinite).
    let fold_point = |step: &[f64], scale: f64| -> Vec<f64> {
        let unit: Vec<f64> = fit
            .unit
            .iter()
            .zip(step)
            .map(|(u, s)| (u + scale * s).clamp(0.0, 1.0))
            .collect();
        least_squares::to_si(hypothesis, &unit)
    };
    let mut folds: Vec<Prediction> = if fitted.len() >= 2 {
        let points: Vec<Vec<f64>> = if fold_steps.is_empty() {
            vec![fit.values.clone(); fitted.len()]
        } else {
            fold_steps.iter().map(|s| fold_point(s, 1.0)).collect()
        };
        let jobs: Vec<(&[f64], usize)> = points
            .iter()
            .zip(fitted)
            .map(|(p, &e)| (p.as_slice(), e))
            .collect();
        engine.run(hypothesis, &jobs)?
    } else {
        Vec::new()
    };
    let mut scale = 1.0;
    for _ in 0..FOLD_STEP_HALVINGS {
        let failed: Vec<usize> = (0..folds.len())
            .filter(|&k| folds[k].is_err() && k < fold_steps.len())
            .collect();
        if failed.is_empty() {
            break;
        }
        scale *= 0.5;
        let points: Vec<Vec<f64>> = failed
            .iter()
            .map(|&k| fold_point(&fold_steps[k], scale))
            .collect();
        let jobs: Vec<(&[f64], usize)> = points
            .iter()
            .zip(&failed)
            .map(|(p, &k)| (p.as_slice(), fitted[k]))
            .collect();
        for (&k, result) in failed.iter().zip(engine.run(hypothesis, &jobs)?) {
            folds[k] = result;
        }
    }
    let holdouts: Vec<usize> = all
        .iter()
        .copied()
        .filter(|i| !fitted.contains(i))
        .collect();
    let mut held_out: Option<f64> = None;
    for (result, &e) in folds.iter().zip(fitted) {
        let error = result
            .as_ref()
            .ok()
            .and_then(|p| error_score(&campaign.experiments[e].recording, p))
            .map_or(f64::INFINITY, |s| s.error * weight(e));
        *held_out.get_or_insert(0.0) += error;
    }
    for &h in &holdouts {
        *held_out.get_or_insert(0.0) += scores[h].map_or(f64::INFINITY, |s| s.error * weight(h));
    }
    let n = fit.residuals.len() as f64;
    let k = fit.values.len() as f64;
    let log_likelihood_term = n * libm::log(fit.chi_square.max(f64::MIN_POSITIVE) / n);
    let assessment = Assessment {
        label: hypothesis.label.clone(),
        constants: hypothesis
            .parameters
            .iter()
            .zip(&fit.values)
            .map(|(p, v)| (p.name.clone(), *v))
            .collect(),
        chi_square: fit.chi_square,
        residuals: fit.residuals.len(),
        constants_fitted: fit.values.len(),
        scores,
        fit_error,
        held_out_error: held_out,
        aic: log_likelihood_term + 2.0 * k,
        bic: log_likelihood_term + k * libm::log(n),
        at_bounds: hypothesis
            .parameters
            .iter()
            .zip(&fit.values)
            .filter_map(|(p, v)| crate::fit::space::at_bound(&p.name, *v, p.lower, p.upper))
            .collect(),
    };
    Ok((assessment, predictions))
}

/// Whether a refit `after` earns its constants against `before`: the Bayesian information
/// criterion drops (by at least `required_drop` when that is positive: a family switch needs
/// [`families::STRONG_EVIDENCE`]) and so does the held-out error (when there is one). `what`
/// names the change in the reason ("term", "family").
fn judge(
    before: &Assessment,
    after: &Assessment,
    what: &str,
    required_drop: f64,
) -> (bool, String) {
    let bic_drop = before.bic - after.bic;
    let held_out_better = match (before.held_out_error, after.held_out_error) {
        (Some(b), Some(a)) => Some(a < b),
        _ => None,
    };
    // A refusal on the information criterion while the held-out error drops is a trade, not
    // a plain rejection (issue 54 item 10): said with both figures.
    let trade = match (before.held_out_error, after.held_out_error) {
        (Some(b), Some(a)) if a < b => format!(
            ", although it cuts the held-out error from {b:.3} to {a:.3} ({:.0} % lower): the \
             fitted recordings do not pay for its constants, the held-out ones favour it",
            100.0 * (1.0 - a / b)
        ),
        _ => String::new(),
    };
    if bic_drop > 0.0 && bic_drop < required_drop && held_out_better != Some(false) {
        return (
            false,
            format!(
                "BIC drops by {bic_drop:.1}, less than the {required_drop} a {what} switch needs \
                 (strong evidence, Kass & Raftery 1995){trade}"
            ),
        );
    }
    match (bic_drop > 0.0, held_out_better) {
        (true, Some(true)) => (
            true,
            format!("BIC drops by {bic_drop:.1} and the held-out error drops"),
        ),
        (true, None) => (
            true,
            format!("BIC drops by {bic_drop:.1} (no experiment can be held out)"),
        ),
        (false, _) => (
            false,
            format!(
                "BIC does not drop ({:+.1}): the {what} does not earn its constants{trade}",
                -bic_drop
            ),
        ),
        (true, Some(false)) => (
            false,
            format!("the held-out error does not drop: the {what} overfits"),
        ),
    }
}

/// The families tried and the winner's index in them with its predictions.
type Alternatives = (Vec<Refit>, Option<(usize, Vec<Vec<f64>>)>);

/// Fit each alternative family ([`families`]) in full and judge it against `before` and the
/// `incumbent` (the accepted term's assessment and name, or `before` and the calibrated
/// model): it wins when its BIC drops by at least [`families::STRONG_EVIDENCE`] and its
/// held-out error drops against both, the lowest BIC among the winners taking it. Returns
/// every family tried and the winner's index with its predictions.
#[allow(clippy::too_many_arguments)]
fn try_alternatives(
    campaign: &Campaign,
    engine: &mut Engine,
    base: &Hypothesis,
    states: &[families::FlowState],
    fitted: &[usize],
    options: &Options,
    before: &Assessment,
    incumbent: (&Assessment, &str),
    cost: &mut Cost,
) -> Result<Alternatives, DiagnoseError> {
    let (incumbent, incumbent_name) = incumbent;
    let mut alternatives: Vec<Refit> = Vec::new();
    let mut winner: Option<(usize, Vec<Vec<f64>>)> = None;
    for alternative in families::alternatives(base, states) {
        let stage_name = format!("alternative family {}", alternative.name);
        engine.stage(&stage_name);
        let mark = engine.points;
        let fit = levenberg_marquardt(
            engine,
            &alternative.hypothesis,
            &alternative.start,
            fitted,
            options.iterations,
        );
        let refit = match fit {
            Ok(fit) => fit,
            // A stop request is not a failed fit.
            Err(_) if crate::fit::interrupt::requested() => {
                return Err(crate::fit::interrupt::Interrupted.into());
            }
            Err(error) => {
                cost.stages.push((stage_name, engine.points - mark));
                alternatives.push(Refit {
                    candidate: alternative.name.clone(),
                    assessment: before.clone(),
                    hypothesis: alternative.hypothesis,
                    accepted: false,
                    reason: format!("the fit failed: {error}"),
                    location: None,
                    refused_for_location: false,
                });
                continue;
            }
        };
        let mut hypothesis = alternative
            .hypothesis
            .with_values(&refit.values)
            .map_err(DiagnoseError::Calibration)?;
        hypothesis.label = alternative.name.clone();
        let (assessment, predictions) = assess(campaign, engine, &hypothesis, &refit, fitted)?;
        cost.stages.push((stage_name, engine.points - mark));
        // A different family is a larger claim than one more term: it needs strong evidence
        // on the BIC scale.
        let (ok, reason) = judge(before, &assessment, "family", families::STRONG_EVIDENCE);
        let beats_incumbent = assessment.bic < incumbent.bic
            && match (incumbent.held_out_error, assessment.held_out_error) {
                (Some(i), Some(a)) => a < i,
                _ => true,
            };
        let best_so_far = winner
            .as_ref()
            .is_none_or(|(w, _)| assessment.bic < alternatives[*w].assessment.bic);
        let wins = ok && beats_incumbent && best_so_far;
        let reason = if ok && beats_incumbent && !best_so_far {
            format!("{reason}, but another family fits better")
        } else if ok && !beats_incumbent {
            format!(
                "{reason}, but it does not beat {incumbent_name} (BIC {:.1} against {:.1})",
                assessment.bic, incumbent.bic
            )
        } else {
            reason
        };
        alternatives.push(Refit {
            candidate: alternative.name.clone(),
            assessment,
            hypothesis,
            accepted: wins,
            reason,
            location: None,
            refused_for_location: false,
        });
        if wins {
            winner = Some((alternatives.len() - 1, predictions));
        }
    }
    if let Some((index, _)) = &winner {
        // Earlier winners lose to the last (lowest-BIC) one.
        let chosen = alternatives[*index].candidate.clone();
        for (i, other) in alternatives.iter_mut().enumerate() {
            if i != *index && other.accepted {
                other.accepted = false;
                other.reason = format!("{}, but {chosen} fits better", other.reason);
            }
        }
    }
    Ok((alternatives, winner))
}

/// Full outcomes (tracked states, fields) of every experiment with `hypothesis` at its current
/// values, for the locate step; `None` where a simulation fails.
fn simulate_outcomes(
    engine: &Engine,
    hypothesis: &Hypothesis,
) -> Result<Vec<Option<crate::experiment::Outcome>>, DiagnoseError> {
    let values = hypothesis.values().map_err(DiagnoseError::Calibration)?;
    let realised = hypothesis
        .realise(&values)
        .map_err(DiagnoseError::Calibration)?;
    Ok(engine
        .experiments
        .iter()
        .map(|e| realised.outcome(e, engine.settings()).ok())
        .collect())
}

/// Locate the misfit of every experiment.
fn locate_all(
    engine: &Engine,
    predictions: &[Vec<f64>],
    outcomes: &[Option<crate::experiment::Outcome>],
    fitted: &[usize],
    alpha: f64,
) -> Vec<ExperimentMisfit> {
    let experiments = engine.experiments;
    let refs: Vec<&crate::experiment::Experiment> = experiments.iter().collect();
    let windows = locate::window_count(&refs).max(1);
    let count = experiments.len().max(1);
    experiments
        .iter()
        .enumerate()
        .map(|(i, e)| {
            locate::locate(
                i,
                e,
                !fitted.contains(&i),
                &predictions[i],
                outcomes.get(i).and_then(|o| o.as_ref()),
                alpha / windows as f64,
                alpha / count as f64,
            )
        })
        .collect()
}

/// A diagnosis with the predictions of every experiment before and (if a term was accepted)
/// after.
pub struct Outcome {
    /// The diagnosis.
    pub diagnosis: Diagnosis,
    /// Predictions of the calibrated model refitted by least squares.
    pub before: Vec<Vec<f64>>,
    /// Predictions of the accepted model.
    pub after: Option<Vec<Vec<f64>>>,
}

/// A refitted term's predictions of every experiment and its fit.
type FittedTerm = (Vec<Vec<f64>>, Fit);

/// Refit the calibrated model with `candidate` (every constant plus the term's, from the
/// calibrated values and the term at its null), assess it and judge it against `before` (its
/// assessment and located misfit): the information criterion and the held-out error, then
/// where the improvement lies ([`location`]).
/// Returns the refit's record and, unless the Levenberg-Marquardt fit failed, its predictions
/// and fit.
#[allow(clippy::too_many_arguments)]
fn refit_candidate(
    campaign: &Campaign,
    engine: &mut Engine,
    candidate: &Candidate,
    base_fit: &Fit,
    fitted: &[usize],
    options: &Options,
    before: (&Assessment, &LocatedMisfit),
    cost: &mut Cost,
) -> Result<(Refit, Option<FittedTerm>), DiagnoseError> {
    let (before, located) = before;
    let stage_name = format!("refit with {}", candidate.name);
    engine.stage(&stage_name);
    let mark = engine.points;
    let (hypothesis, start) = candidate.refit(&base_fit.values);
    let refit = match levenberg_marquardt(engine, &hypothesis, &start, fitted, options.iterations) {
        Ok(fit) => fit,
        // A stop request is not a failed refit.
        Err(_) if crate::fit::interrupt::requested() => {
            return Err(crate::fit::interrupt::Interrupted.into());
        }
        Err(error) => {
            cost.stages.push((stage_name, engine.points - mark));
            return Ok((
                Refit {
                    candidate: candidate.name.clone(),
                    assessment: before.clone(),
                    hypothesis,
                    accepted: false,
                    reason: format!("the refit failed: {error}"),
                    location: None,
                    refused_for_location: false,
                },
                None,
            ));
        }
    };
    let mut hypothesis = hypothesis
        .with_values(&refit.values)
        .map_err(DiagnoseError::Calibration)?;
    hypothesis.label = candidate.name.clone();
    let (mut assessment, predictions) = assess(campaign, engine, &hypothesis, &refit, fitted)?;
    if candidate.switches_rate_treatment {
        // The switch is a constant of the model too.
        let n = assessment.residuals as f64;
        assessment.constants_fitted += 1;
        assessment.aic += 2.0;
        assessment.bic += libm::log(n);
    }
    cost.stages.push((stage_name, engine.points - mark));
    let (earned, mut reason) = judge(before, &assessment, "term", 0.0);
    // Location-consistent acceptance: the improvement must lie where the misfit was located.
    let location = located.check(&campaign.experiments, &predictions, options.alpha);
    let refused_for_location = earned && location.as_ref().is_some_and(|c| !c.consistent);
    // Where the improvement lies is said of a term that earned its constant.
    if let Some(check) = location.as_ref().filter(|_| earned) {
        let joint = if refused_for_location { ", but" } else { ";" };
        reason = format!("{reason}{joint} {}", check.describe());
    }
    Ok((
        Refit {
            candidate: candidate.name.clone(),
            assessment,
            hypothesis,
            accepted: earned && !refused_for_location,
            reason,
            location,
            refused_for_location,
        },
        Some((predictions, refit)),
    ))
}

/// Of the terms that earn their constant, the lowest BIC is kept (terms of one physics, e.g.
/// adiabatic heating and a heating transition, compete here); the refit just pushed on
/// `refits` displaces the `accepted` one only on positive evidence (a BIC lower by at least
/// [`POSITIVE_EVIDENCE`], Kass & Raftery 1995), so near-equivalent terms keep the rank order.
fn keep_best(
    refits: &mut [Refit],
    accepted: &mut Option<(usize, FittedTerm)>,
    fitted_term: FittedTerm,
) {
    let last = refits.len() - 1;
    if !refits[last].accepted {
        return;
    }
    let better = accepted.as_ref().is_none_or(|(index, _)| {
        refits[*index].assessment.bic - refits[last].assessment.bic >= POSITIVE_EVIDENCE
    });
    if better {
        if let Some((index, _)) = accepted.as_ref() {
            let winner = refits[last].candidate.clone();
            let loser = &mut refits[*index];
            loser.accepted = false;
            loser.reason = format!("{}, but {winner} fits better", loser.reason);
        }
        *accepted = Some((last, fitted_term));
    } else {
        let winner = accepted
            .as_ref()
            .map(|(index, _)| refits[*index].candidate.clone())
            .unwrap_or_default();
        refits[last].accepted = false;
        refits[last].reason = format!(
            "{}, but not by the {POSITIVE_EVIDENCE} BIC below {winner} that displacing it needs",
            refits[last].reason
        );
    }
}

/// The score tests of every term of `library`, ranked: lowest p-value first, the larger
/// statistic first among equal p-values.
fn ranked_score_tests(
    engine: &mut Engine,
    library: &[Candidate],
    base_fit: &Fit,
    fitted: &[usize],
    alpha: f64,
) -> Result<Vec<ScoreTest>, DiagnoseError> {
    let mut tests = score::score_tests(engine, library, base_fit, fitted, alpha)?;
    tests.sort_by(|a, b| {
        a.p_value
            .total_cmp(&b.p_value)
            .then(b.statistic.total_cmp(&a.statistic))
    });
    Ok(tests)
}

/// The misfit of `hypothesis` (its `predictions`), located with the states of its simulations.
fn misfit_of(
    engine: &Engine,
    hypothesis: &Hypothesis,
    predictions: &[Vec<f64>],
    fitted: &[usize],
    alpha: f64,
) -> Result<Vec<ExperimentMisfit>, DiagnoseError> {
    let outcomes = simulate_outcomes(engine, hypothesis)?;
    Ok(locate_all(engine, predictions, &outcomes, fitted, alpha))
}

/// The refits of the library's terms, and the accepted one's index with its predictions and
/// fit.
type Refits = (Vec<Refit>, Option<(usize, FittedTerm)>);

/// The refits of the library's terms, in two stages: the significant terms in rank order;
/// then, if none was accepted, the best-ranked admissible terms the score test under-rates,
/// each also judged by its likelihood ratio. Returns every refit and the accepted one's index
/// with its predictions.
#[allow(clippy::too_many_arguments)]
fn refit_terms(
    campaign: &Campaign,
    engine: &mut Engine,
    library: &[Candidate],
    tests: &[ScoreTest],
    base_fit: &Fit,
    fitted: &[usize],
    options: &Options,
    before: (&Assessment, &LocatedMisfit),
    cost: &mut Cost,
) -> Result<Refits, DiagnoseError> {
    let mut refits = Vec::new();
    let mut accepted: Option<(usize, FittedTerm)> = None;
    // Two stages: the significant terms in rank order; then, if none was accepted, the
    // best-ranked admissible terms the score test under-rates, each also judged by the drop
    // its refit achieves (a likelihood-ratio test at the same level, `likelihood_ratio`).
    let ranges = row_ranges(&campaign.experiments, fitted);
    let terms = tests.len().max(1) as f64;
    for by_ratio in [false, true] {
        if by_ratio && accepted.is_some() {
            break;
        }
        let stage: Vec<&ScoreTest> = tests
            .iter()
            .filter(|t| {
                if by_ratio {
                    !t.significant && t.statistic > 0.0
                } else {
                    t.significant
                }
            })
            .take(options.max_refits)
            .collect();
        for test in stage {
            let Some(candidate) = library.iter().find(|c| c.name == test.name) else {
                continue;
            };
            let (mut refit, fitted_term) = refit_candidate(
                campaign, engine, candidate, base_fit, fitted, options, before, cost,
            )?;
            let Some((predictions, fit)) = fitted_term else {
                refits.push(refit);
                continue;
            };
            if by_ratio {
                let ratio = likelihood_ratio::likelihood_ratio(
                    &base_fit.residuals,
                    &fit.residuals,
                    &ranges,
                    fit.values.len(),
                    candidate.one_sided,
                );
                // The variant of a term tried over a grid of a shape constant was chosen by
                // its score on the same data: Bonferroni over the grid too, as for the score
                // test.
                let variants = library
                    .iter()
                    .filter(|c| c.group == candidate.group)
                    .count()
                    .max(1) as f64;
                let p_value = (ratio.single_p_value * variants * terms).min(1.0);
                let score_p = test.p_value;
                if p_value < options.alpha {
                    refit.reason = format!(
                        "score test p {score_p:.1e}, but its refit's likelihood ratio is \
                         significant (drop {:.1}, T {:.1}, p {p_value:.1e}); {}",
                        ratio.drop, ratio.statistic, refit.reason
                    );
                } else {
                    refit.reason = format!(
                        "score test p {score_p:.1e} and its refit's likelihood ratio p \
                         {p_value:.1e} (drop {:.1}, T {:.1}): not significant at {}; {}",
                        ratio.drop, ratio.statistic, options.alpha, refit.reason
                    );
                    refit.accepted = false;
                }
            }
            refits.push(refit);
            keep_best(&mut refits, &mut accepted, (predictions, fit));
        }
    }
    Ok((refits, accepted))
}

/// The accepted rounds, the searches after the first, and the last accepted model's refit
/// record with its predictions.
type Rounds = (Vec<Round>, Vec<RoundSearch>, Option<(Refit, Vec<Vec<f64>>)>);

/// Rounds after the first: from the term the first round `first` (its refits, the accepted
/// one's index with its predictions and fit, and its score tests) accepted, search the library
/// again from the extended model (every constant and the new term refitted), judge each term
/// against that model as the first round judged against the calibrated one (score test,
/// likelihood ratio, BIC and held-out error), and go on until no term earns its place or
/// [`Options::max_rounds`] were accepted. A term whose constant the model already fits, or of
/// a group already accepted, is not offered again.
fn further_rounds(
    campaign: &Campaign,
    engine: &mut Engine,
    first: (&[Refit], Option<(usize, FittedTerm)>, &[ScoreTest]),
    before: &Assessment,
    fitted: &[usize],
    options: &Options,
    cost: &mut Cost,
) -> Result<Rounds, DiagnoseError> {
    let (refits, accepted, tests) = first;
    let mut rounds: Vec<Round> = Vec::new();
    let mut later_rounds: Vec<RoundSearch> = Vec::new();
    let mut current: Option<(Refit, Vec<Vec<f64>>)> = None;
    let mut groups: Vec<String> = Vec::new();
    let mut round_before = before.clone();
    let mut next = accepted.map(|(index, term)| (refits[index].clone(), term, tests.to_vec()));
    while let Some((refit, (predictions, fit), round_tests)) = next.take() {
        let number = rounds.len() + 1;
        let test = round_tests.iter().find(|t| t.name == refit.candidate);
        rounds.push(Round {
            round: number,
            accepted: refit.candidate.clone(),
            physics: test.map_or_else(|| refit.candidate.clone(), |t| t.physics.clone()),
            explained: test.map_or(0.0, |t| t.share),
            before: (
                round_before.fit_error,
                round_before.held_out_error,
                round_before.bic,
            ),
            after: (
                refit.assessment.fit_error,
                refit.assessment.held_out_error,
                refit.assessment.bic,
            ),
        });
        round_before = refit.assessment.clone();
        let base = refit.hypothesis.clone();
        current = Some((refit, predictions));
        if number >= options.max_rounds {
            break;
        }
        let stage_name = format!("round {}: score tests", number + 1);
        engine.stage(&stage_name);
        let mark = engine.points;
        let outcomes = simulate_outcomes(engine, &base)?;
        let round_located = match &current {
            Some((_, predictions)) => LocatedMisfit::new(&locate_all(
                engine,
                predictions,
                &outcomes,
                fitted,
                options.alpha,
            )),
            None => LocatedMisfit::new(&[]),
        };
        let (library, _) = candidates::library(
            &base,
            campaign,
            &candidates::Visited::from_outcomes(&outcomes),
        );
        if let Some(name) = rounds.last().map(|r| r.accepted.clone()) {
            if let Some(group) = library
                .iter()
                .find(|c| c.name == name)
                .map(|c| c.group.clone())
            {
                groups.push(group);
            }
            groups.push(name);
        }
        let library: Vec<Candidate> = library
            .into_iter()
            .filter(|c| {
                !base.parameters.iter().any(|p| p.name == c.parameter.name)
                    && !groups.contains(&c.group)
                    && !groups.contains(&c.name)
            })
            .collect();
        let round_tests = ranked_score_tests(engine, &library, &fit, fitted, options.alpha)?;
        cost.stages.push((stage_name, engine.points - mark));
        let (round_refits, round_accepted) = refit_terms(
            campaign,
            engine,
            &library,
            &round_tests,
            &fit,
            fitted,
            options,
            (&round_before, &round_located),
            cost,
        )?;
        next = round_accepted
            .map(|(index, term)| (round_refits[index].clone(), term, round_tests.clone()));
        later_rounds.push(RoundSearch {
            round: number + 1,
            tests: round_tests,
            refits: round_refits,
        });
    }
    Ok((rounds, later_rounds, current))
}

/// The calibrated `model` of `campaign` as a hypothesis, its selected constants written in.
fn calibrated_hypothesis(
    campaign: &Campaign,
    model: &ModelResult,
) -> Result<Hypothesis, DiagnoseError> {
    let entry = campaign.model(&model.model).ok_or_else(|| {
        DiagnoseError::Calibration(format!(
            "model `{}` of result.json is not in the campaign",
            model.model
        ))
    })?;
    let space = campaign.space(entry);
    Hypothesis::base(&campaign.base, &space, &model.selected.values)
        .map_err(DiagnoseError::Calibration)
}

/// Diagnose the calibrated `model` (constants `values`) of `campaign`. Simulations run through
/// `executor` (this machine's pool or Slurm) and are logged in `log` (a rerun replays them).
pub fn diagnose(
    campaign: &Campaign,
    model: &ModelResult,
    options: &Options,
    executor: &mut dyn Executor,
    log: Option<&Path>,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<Outcome, DiagnoseError> {
    let base = calibrated_hypothesis(campaign, model)?;
    let start = base.values().map_err(DiagnoseError::Calibration)?;
    let fitted = campaign.fitted();
    let mut engine = Engine::new(campaign, executor, log, progress)?;
    let mut cost = Cost::default();
    let stage = |engine: &Engine, name: &str, before: usize, cost: &mut Cost| {
        cost.stages.push((name.into(), engine.points - before));
    };

    engine.stage("least-squares refit of the calibrated model");
    let mark = engine.points;
    let base_fit = levenberg_marquardt(&mut engine, &base, &start, &fitted, options.iterations)?;
    let base = base
        .with_values(&base_fit.values)
        .map_err(DiagnoseError::Calibration)?;
    let (before, predictions_before) = assess(campaign, &mut engine, &base, &base_fit, &fitted)?;
    stage(&engine, "refit of the calibrated model", mark, &mut cost);

    engine.stage("locate");
    let outcomes = simulate_outcomes(&engine, &base)?;
    let misfit_before = locate_all(
        &engine,
        &predictions_before,
        &outcomes,
        &fitted,
        options.alpha,
    );

    let state_misfit = state_space::bin_by_state(&campaign.experiments, &misfit_before, &outcomes);

    // Simulation or material: the located FE experiments once more, refined and on their
    // other solver. When every located misfit moves with the method, the material is not
    // changed for it.
    engine.stage("simulation or material");
    let numerical = numerical::check(&engine, &base, &predictions_before, &misfit_before)
        .map_err(DiagnoseError::Calibration)?;
    let located: Vec<usize> = misfit_before
        .iter()
        .filter(|m| m.structured && !m.holdout)
        .map(|m| m.index)
        .collect();
    let attribute = located.is_empty()
        || !located
            .iter()
            .all(|i| numerical.iter().any(|c| c.experiment == *i && c.numerical));

    engine.stage("score tests");
    let mark = engine.points;
    let (library, not_applicable) = if attribute {
        candidates::library(
            &base,
            campaign,
            &candidates::Visited::from_outcomes(&outcomes),
        )
    } else {
        (Vec::new(), Vec::new())
    };
    let tests = if attribute {
        ranked_score_tests(&mut engine, &library, &base_fit, &fitted, options.alpha)?
    } else {
        Vec::new()
    };
    stage(&engine, "score tests", mark, &mut cost);

    let located = LocatedMisfit::new(&misfit_before);
    let (refits, accepted) = refit_terms(
        campaign,
        &mut engine,
        &library,
        &tests,
        &base_fit,
        &fitted,
        options,
        (&before, &located),
        &mut cost,
    )?;

    // Rounds: from each accepted term's refit, search again until nothing earns its place.
    let (rounds, later_rounds, current) = further_rounds(
        campaign,
        &mut engine,
        (&refits, accepted, &tests),
        &before,
        &fitted,
        options,
        &mut cost,
    )?;

    let (mut misfit_after, mut predictions_after, mut accepted_name) = match &current {
        Some((refit, predictions)) => (
            Some(misfit_of(
                &engine,
                &refit.hypothesis,
                predictions,
                &fitted,
                options.alpha,
            )?),
            Some(predictions.clone()),
            rounds.first().map(|r| r.accepted.clone()),
        ),
        None => (None, None, None),
    };

    // Non-nested alternatives, when what is left is still structured.
    let left_structured = misfit_after
        .as_ref()
        .unwrap_or(&misfit_before)
        .iter()
        .any(|m| m.structured);
    let mut alternatives = Vec::new();
    let mut replacement = None;
    if left_structured && attribute {
        let incumbent = match &current {
            Some((refit, _)) => refit.assessment.clone(),
            None => before.clone(),
        };
        let incumbent_name = if rounds.is_empty() {
            "the calibrated model".to_string()
        } else {
            rounds
                .iter()
                .map(|r| r.accepted.as_str())
                .collect::<Vec<_>>()
                .join(" + ")
        };
        let states = families::plastic_states(&outcomes);
        let (tried, winner) = try_alternatives(
            campaign,
            &mut engine,
            &base,
            &states,
            &fitted,
            options,
            &before,
            (&incumbent, &incumbent_name),
            &mut cost,
        )?;
        alternatives = tried;
        if let Some((index, predictions)) = winner {
            let chosen = &alternatives[index];
            misfit_after = Some(misfit_of(
                &engine,
                &chosen.hypothesis,
                &predictions,
                &fitted,
                options.alpha,
            )?);
            predictions_after = Some(predictions);
            accepted_name = Some(chosen.candidate.clone());
            replacement = Some(chosen.candidate.clone());
        }
    }
    cost.simulated = engine.simulated;
    cost.replayed = engine.replayed;
    let mut diagnosis = Diagnosis {
        campaign: campaign.file.name.clone(),
        model: model.model.clone(),
        options: options.clone(),
        before,
        misfit_before,
        state_misfit,
        numerical,
        tests,
        not_applicable,
        refits,
        misfit_after,
        accepted: accepted_name,
        rounds,
        later_rounds,
        alternatives,
        replacement,
        verdict: String::new(),
        cost,
    };
    diagnosis.verdict = report::verdict(campaign, &diagnosis);
    Ok(Outcome {
        diagnosis,
        before: predictions_before,
        after: predictions_after,
    })
}

#[cfg(test)]
mod judge_tests {
    use super::*;

    fn assessment(bic: f64, held_out: Option<f64>) -> Assessment {
        Assessment {
            label: String::new(),
            constants: Vec::new(),
            chi_square: 1.0,
            residuals: 10,
            constants_fitted: 3,
            scores: Vec::new(),
            fit_error: 1.0,
            held_out_error: held_out,
            aic: bic,
            bic,
            at_bounds: Vec::new(),
        }
    }

    #[test]
    fn a_candidate_the_information_criterion_refuses_shows_its_held_out_trade() {
        // GOAL: issue 54 item 10: a family that cuts the held-out error strongly while its BIC
        //       rises (or drops by less than a family switch needs) is not rejected silently:
        //       the reason gives the trade with both held-out figures.
        // SETUP: the copper Taylor case's figures (docs/diagnosis.md): held-out 0.247 ->
        //        0.133 with the BIC up by 2.0, then down by 0.4 against the 6 a family needs;
        //        a candidate whose held-out error rises; nothing held out.
        // REFERENCE: refused in every case; the first two reasons name 0.247, 0.133 and the
        //        46 % cut; the others say nothing of a trade.
        let before = assessment(100.0, Some(0.247));
        let (ok, reason) = judge(&before, &assessment(102.0, Some(0.133)), "family", 6.0);
        assert!(!ok);
        assert!(
            reason.contains("from 0.247 to 0.133 (46 % lower)")
                && reason.contains("the held-out ones favour it"),
            "{reason}"
        );
        let (ok, reason) = judge(&before, &assessment(99.6, Some(0.133)), "family", 6.0);
        assert!(!ok && reason.contains("less than the 6") && reason.contains("0.133"));
        let (ok, reason) = judge(&before, &assessment(102.0, Some(0.3)), "family", 6.0);
        assert!(!ok && !reason.contains("favour"), "{reason}");
        let none = assessment(100.0, None);
        let (ok, reason) = judge(&none, &assessment(102.0, None), "term", 0.0);
        assert!(!ok && !reason.contains("favour"), "{reason}");
    }
}
