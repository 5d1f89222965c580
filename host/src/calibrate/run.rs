//! The calibration protocol (seed 000 sec. 4): for each model, independent optimisation
//! instances on the fitted experiments; optionally leave-one-out folds (fit on n-1, then score
//! every fold's best on all n and keep the best, as seed 000 does); model selection across the
//! campaign's models. Batches of candidates are simulated in parallel; every result is logged
//! as it ends, and a resumed run replays the log instead of simulating again.

use super::polish::NelderMead;
use crate::experiment::Outcome;
use crate::fit::campaign::{Campaign, LeaveOneOut, UncertaintyFor};
use crate::fit::executor::{Batch, Candidate, Executor, ExecutorError, Origin};
use crate::fit::fidelity::{Correction, Fidelity, FidelitySummary};
use crate::fit::log::{Entry, Key, LogError, SimulationLog};
use crate::fit::objective::{score, Evaluation, Status};
use crate::fit::result::{Baseline, InstanceResult, ModelResult, NamedConstant};
use crate::fit::space::constants_at_bounds;
use crate::fit::unit_cube;
use crate::fit::ModelSpace;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// An ask/tell optimiser over a model's box of constants (physical units).
pub trait Proposer {
    /// The next batch of candidates (empty when the budget is spent).
    fn ask(&mut self) -> Vec<Vec<f64>>;
    /// Their objective values; `None` for failed or infeasible candidates.
    fn tell(&mut self, points: &[Vec<f64>], values: &[Option<f64>]) -> Result<(), String>;
}

/// Builds a proposer for a model space, a budget, a batch size and a seed.
pub type ProposerFactory<'a> =
    dyn Fn(&ModelSpace, usize, usize, u64) -> Box<dyn Proposer> + Sync + 'a;

/// Why a calibration stopped.
#[derive(Debug, thiserror::Error)]
pub enum CalibrateError {
    /// The simulation log failed.
    #[error(transparent)]
    Log(#[from] LogError),
    /// No candidate of a model could be simulated: the model, and why the first candidate
    /// failed (if one was tried).
    #[error("model {0}: no candidate could be simulated{reason}", reason = first_failure(.1))]
    NoFeasibleCandidate(String, Option<String>),
    /// The thread pool could not be built.
    #[error("thread pool: {0}")]
    Threads(String),
    /// The optimiser rejected its input.
    #[error("optimiser: {0}")]
    Optimiser(String),
    /// The executor (Slurm) could not run the simulations.
    #[error("executor: {0}")]
    Executor(String),
    /// The least-squares finish could not start (its log or thread pool).
    #[error("least-squares finish: {0}")]
    LeastSquares(String),
    /// Stopped on request (SIGINT, SIGTERM) after the batch in flight was logged.
    #[error(transparent)]
    Interrupted(#[from] crate::fit::interrupt::Interrupted),
}

impl From<ExecutorError> for CalibrateError {
    /// Variant for variant: the messages a calibration has always given.
    fn from(error: ExecutorError) -> Self {
        match error {
            ExecutorError::Log(e) => Self::Log(e),
            ExecutorError::Threads(e) => Self::Threads(e),
            ExecutorError::Executor(e) => Self::Executor(e),
        }
    }
}

/// The tail of [`CalibrateError::NoFeasibleCandidate`]'s message: why the first candidate
/// failed, when one was tried.
fn first_failure(reason: &Option<String>) -> String {
    match reason {
        Some(reason) => format!("; the first failed: {reason}"),
        None => String::new(),
    }
}

/// Progress reported after every batch: `(model, fold, instance, candidates done, budget, best so far)`.
pub type Progress<'a> = dyn FnMut(&str, Option<&str>, usize, usize, usize, Option<f64>) + 'a;

/// Settings of a run beyond the campaign file.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Override of the campaign's budget (e.g. for quick checks).
    pub budget: Option<usize>,
    /// Override of the campaign's instances.
    pub instances: Option<usize>,
    /// Override of leave-one-out.
    pub leave_one_out: Option<LeaveOneOut>,
    /// Override of the polish budget.
    pub polish: Option<usize>,
    /// Override of the least-squares finish's iterations.
    pub least_squares: Option<usize>,
    /// Also simulate what the report draws (every model's selected constants on every
    /// experiment, its starting constants on the held-out ones) in the pool of the
    /// intervals' forward differences ([`Calibration::simulated`]).
    pub outcomes: bool,
}

/// Where an instance's candidates go: its model space, fold, number, experiments, seed and
/// the progress bar's total.
struct Place<'p> {
    space: &'p ModelSpace,
    fold: Option<&'p str>,
    instance: usize,
    experiments: &'p [usize],
    seed: u64,
    total: usize,
}

/// The running record of one instance: the best candidate, the convergence history and the
/// counts of simulated and failed candidates.
#[derive(Default)]
struct Tally {
    /// The best simulated candidate (a corrected coarse prediction never is one).
    best: Option<(Evaluation, f64)>,
    /// Multi-fidelity: the best corrected coarse candidate and its index, re-simulated on
    /// the fine meshes at the end of the search if it beats `best`.
    best_corrected: Option<(Evaluation, f64, usize)>,
    /// Multi-fidelity: the search's coarse candidates and fine checks.
    fidelity: Option<FidelitySummary>,
    history: Vec<Option<f64>>,
    simulated: usize,
    failed: usize,
    infeasible: usize,
    /// Why the first failed or infeasible candidate was rejected.
    first_failure: Option<String>,
}

impl Tally {
    /// Record one evaluated candidate, its index and its objective value (`None`: failed or
    /// infeasible).
    fn record(&mut self, evaluation: Evaluation, index: usize, value: Option<f64>) {
        match &evaluation.status {
            Status::Ok => self.simulated += 1,
            Status::Failed(reason) => {
                self.simulated += 1;
                self.failed += 1;
                self.first_failure.get_or_insert_with(|| reason.clone());
            }
            Status::Infeasible(reason) => {
                self.infeasible += 1;
                self.first_failure.get_or_insert_with(|| reason.clone());
            }
        }
        self.offer_at(&evaluation, index, value);
        self.history.push(self.best_value());
    }

    /// Offer an earlier simulation (a warm start) as a candidate for the best, without
    /// counting it as simulated by this instance or adding to its history.
    fn offer(&mut self, evaluation: &Evaluation, value: Option<f64>) {
        self.offer_at(evaluation, usize::MAX, value);
    }

    /// `evaluation` as the best (simulated) or best corrected candidate if it beats it.
    fn offer_at(&mut self, evaluation: &Evaluation, index: usize, value: Option<f64>) {
        let Some(value) = value else {
            return;
        };
        if evaluation.corrected {
            if self
                .best_corrected
                .as_ref()
                .is_none_or(|(_, b, _)| value < *b)
            {
                self.best_corrected = Some((evaluation.clone(), value, index));
            }
        } else if self.best.as_ref().is_none_or(|(_, b)| value < *b) {
            self.best = Some((evaluation.clone(), value));
        }
    }

    /// The best value the search has seen: simulated, or (multi-fidelity) a corrected coarse
    /// prediction, the optimiser's view.
    fn best_value(&self) -> Option<f64> {
        let simulated = self.best.as_ref().map(|b| b.1);
        let corrected = self.best_corrected.as_ref().map(|b| b.1);
        match (simulated, corrected) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }
}

struct Runner<'a> {
    campaign: &'a Campaign,
    log: SimulationLog,
    executor: &'a mut dyn Executor,
    factory: &'a ProposerFactory<'a>,
    progress: &'a mut Progress<'a>,
    budget: usize,
    batch: usize,
    polish: usize,
    least_squares: usize,
    stop_at_noise_floor: bool,
    fold_budget: Option<usize>,
    /// Where the least-squares finishes log their simulations (for resume).
    output: PathBuf,
    /// Multi-fidelity: each model's correction, learned from its fine checks in the order
    /// they ran (instances and folds of a model share it: a pair depends only on the
    /// constants, not on which experiments a fold fits).
    corrections: BTreeMap<String, Correction>,
}

impl Runner<'_> {
    /// Evaluate a batch through the executor, reusing logged results; log each new one as it
    /// finishes.
    fn evaluate_batch(
        &mut self,
        keys: &[Key],
        points: &[Vec<f64>],
        space: &ModelSpace,
        experiments: &[usize],
        seed: u64,
    ) -> Result<Vec<Evaluation>, CalibrateError> {
        let mut results = Vec::with_capacity(points.len());
        // Every key of a batch names the same mesh.
        let fidelity = keys.first().map_or(Fidelity::Fine, |k| k.fidelity);
        for (key, point) in keys.iter().zip(points) {
            let mut logged = self.log.lookup(key, point)?;
            if let Some(evaluation) = &mut logged {
                // A log written before stoss named its values carries none.
                evaluation.label_positional(self.campaign, space);
            }
            results.push(logged);
        }
        let fresh: Vec<usize> = (0..points.len())
            .filter(|&i| results[i].is_none())
            .collect();
        if fresh.is_empty() {
            return Ok(results.into_iter().flatten().collect());
        }
        // A stop requested before new simulations start: none is started.
        crate::fit::interrupt::check()?;
        let batch = Batch {
            campaign: self.campaign,
            space,
            experiments,
            seed,
            candidates: fresh
                .iter()
                .map(|&i| Candidate {
                    key: &keys[i],
                    values: &points[i],
                })
                .collect(),
            fidelity,
        };
        // Each new evaluation is appended to the log as soon as it finishes (a run killed in
        // the middle of a batch loses only the simulations still running); the log is keyed,
        // so the order of its lines does not matter.
        let log = std::sync::Mutex::new(&mut self.log);
        let record = |index: usize, evaluation: &Evaluation, origin: &Origin| {
            log.lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .append(Entry {
                    key: batch.candidates[index].key.clone(),
                    seed,
                    evaluation: evaluation.clone(),
                    origin: Some(origin.clone()),
                })
                .map_err(ExecutorError::from)
        };
        let evaluations = self.executor.evaluate(&batch, &record)?;
        // A stop requested while the batch ran: it is logged; nothing after it starts.
        crate::fit::interrupt::check()?;
        for (&i, evaluation) in fresh.iter().zip(evaluations) {
            results[i] = Some(evaluation);
        }
        Ok(results.into_iter().flatten().collect())
    }

    /// Whether `tally`'s best candidate fits `experiments` within their recorded noise (the
    /// stop rule `stop_at_noise_floor`): the chi-square of its whitened residuals, from each
    /// experiment's RMS `chi` and point count, at most `nu + 2 sqrt(2 nu)` with `nu` the
    /// points less the `constants` fitted.
    fn at_noise_floor(&self, tally: &Tally, experiments: &[usize], constants: usize) -> bool {
        let Some((best, _)) = tally.best.as_ref() else {
            return false;
        };
        let mut chi_square = 0.0;
        let mut points = 0usize;
        for &i in experiments {
            let Some(Some(score)) = best.scores.get(i) else {
                return false;
            };
            let n = self.campaign.experiments[i].recording.len();
            chi_square += score.chi * score.chi * n as f64;
            points += n;
        }
        let nu = points.saturating_sub(constants).max(1) as f64;
        chi_square <= nu + 2.0 * libm::sqrt(2.0 * nu)
    }

    /// Simulate one candidate `point` of the instance at `place` as its `index`-th (logged,
    /// reused on resume), record it in `tally` and `seen`, advance `index` and report
    /// progress. Returns its objective value (`None`: failed or infeasible).
    fn score_one(
        &mut self,
        place: &Place<'_>,
        index: &mut usize,
        point: &[f64],
        tally: &mut Tally,
        seen: &mut Vec<Evaluation>,
    ) -> Result<Option<f64>, CalibrateError> {
        let key = Key {
            model: place.space.name.clone(),
            fold: place.fold.map(str::to_string),
            instance: place.instance,
            index: *index,
            fidelity: Default::default(),
        };
        let evaluation = self
            .evaluate_batch(
                &[key],
                &[point.to_vec()],
                place.space,
                place.experiments,
                place.seed,
            )?
            .remove(0);
        let value = if evaluation.status == Status::Ok {
            evaluation.total(self.campaign, place.experiments)
        } else {
            None
        };
        seen.push(evaluation.clone());
        tally.record(evaluation, *index, value);
        *index += 1;
        (self.progress)(
            &place.space.name,
            place.fold,
            place.instance,
            *index,
            place.total,
            tally.best_value(),
        );
        Ok(value)
    }

    /// The constants (in the model space's order) that `iterations` of the bounded
    /// Levenberg-Marquardt fit reach from `start` on the whitened residuals of `experiments`
    /// ([`crate::fit::levenberg_marquardt`]), its simulations logged to
    /// `least-squares-<model>-<fold>-<instance>.jsonl` in the output folder (a resumed run
    /// replays them). `None` when the model is not a J2 metal or the fit fails: the finish is
    /// then skipped, not the calibration.
    fn least_squares_finish(
        &mut self,
        space: &ModelSpace,
        fold: Option<&str>,
        instance: usize,
        experiments: &[usize],
        start: &[f64],
        iterations: usize,
    ) -> Result<Option<Vec<f64>>, CalibrateError> {
        use crate::fit::{levenberg_marquardt, Engine, FitError, Hypothesis, Progress};
        let Ok(hypothesis) = Hypothesis::base(&self.campaign.base, space, start) else {
            return Ok(None);
        };
        let Ok(values) = hypothesis.values() else {
            return Ok(None);
        };
        let fold_name: String = fold
            .unwrap_or("all")
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect();
        let log = self.output.join(format!(
            "least-squares-{}-{fold_name}-{instance}.jsonl",
            space.name
        ));
        let mut quiet = |_: Progress<'_>| {};
        let mut engine = Engine::new(self.campaign, &mut *self.executor, Some(&log), &mut quiet)
            .map_err(|e| CalibrateError::LeastSquares(e.to_string()))?;
        match levenberg_marquardt(&mut engine, &hypothesis, &values, experiments, iterations) {
            Ok(fit) => Ok(Some(fit.values)),
            // The executor could not run the simulations: the calibration's error, as in
            // its batches.
            Err(FitError::Executor(error)) => Err(error.into()),
            Err(FitError::Interrupted(stop)) => Err(stop.into()),
            Err(_) => Ok(None),
        }
    }

    /// The proposer's batches up to `budget` candidates (or the noise floor): each batch
    /// simulated, tallied and told back on ln(error).
    fn propose(
        &mut self,
        place: &Place<'_>,
        proposer: &mut dyn Proposer,
        budget: usize,
        index: &mut usize,
        tally: &mut Tally,
        seen: &mut Vec<Evaluation>,
    ) -> Result<(), CalibrateError> {
        let space = place.space;
        while *index < budget {
            let mut points = proposer.ask();
            if points.is_empty() {
                break;
            }
            points.truncate(budget - *index);
            let evaluations = self.search_batch(place, *index, &points, tally)?;
            let values: Vec<Option<f64>> = evaluations
                .iter()
                .map(|e| value_of(self.campaign, e, place.experiments))
                .collect();
            seen.extend(evaluations.iter().cloned());
            for (k, (evaluation, value)) in evaluations.into_iter().zip(&values).enumerate() {
                tally.record(evaluation, *index + k, *value);
            }
            // The surrogate models ln(error): errors are positive and heavy-tailed (from the
            // noise floor up to orders of magnitude above it), which a GP fits far better in
            // log space; the transform is monotone, so the optimum is unchanged.
            let surrogate_values: Vec<Option<f64>> = values
                .iter()
                .map(|v| v.map(|e| libm::log(e.max(1e-300))))
                .collect();
            proposer
                .tell(&points, &surrogate_values)
                .map_err(CalibrateError::Optimiser)?;
            *index += points.len();
            (self.progress)(
                &space.name,
                place.fold,
                place.instance,
                *index,
                place.total,
                tally.best_value(),
            );
            if self.stop_at_noise_floor
                && self.at_noise_floor(tally, place.experiments, space.dimension())
            {
                break;
            }
        }
        Ok(())
    }

    /// The key of the candidate `index` of the instance at `place`, on `fidelity`.
    fn key(place: &Place<'_>, index: usize, fidelity: Fidelity) -> Key {
        Key {
            model: place.space.name.clone(),
            fold: place.fold.map(str::to_string),
            instance: place.instance,
            index,
            fidelity,
        }
    }

    /// The experiments of `place` that have a coarse fidelity (empty: a single-fidelity
    /// search).
    fn coarse_experiments(&self, place: &Place<'_>) -> Vec<usize> {
        place
            .experiments
            .iter()
            .copied()
            .filter(|&i| self.campaign.coarse.get(i).is_some_and(Option::is_some))
            .collect()
    }

    /// Simulate a batch of the search (the design and the proposals), its first candidate
    /// the instance's `first`-th. Single-fidelity: as they are. Multi-fidelity: every
    /// candidate on the coarse meshes; those whose index is a multiple of `fine_every` also on
    /// the fine ones (fine checks: the correction is measured on them, then learns from
    /// them, and they count as simulated); the rest corrected. Returns the evaluations the
    /// optimiser is told.
    fn search_batch(
        &mut self,
        place: &Place<'_>,
        first: usize,
        points: &[Vec<f64>],
        tally: &mut Tally,
    ) -> Result<Vec<Evaluation>, CalibrateError> {
        let (space, experiments, seed) = (place.space, place.experiments, place.seed);
        let coarse = self.coarse_experiments(place);
        if coarse.is_empty() {
            let keys: Vec<Key> = (0..points.len())
                .map(|k| Self::key(place, first + k, Fidelity::Fine))
                .collect();
            return self.evaluate_batch(&keys, points, space, experiments, seed);
        }
        let keys: Vec<Key> = (0..points.len())
            .map(|k| Self::key(place, first + k, Fidelity::Coarse))
            .collect();
        let mut evaluations = self.evaluate_batch(&keys, points, space, experiments, seed)?;
        let every = self.campaign.file.optimiser.fine_every.max(1);
        let checked: Vec<usize> = (0..points.len())
            .filter(|&k| (first + k).is_multiple_of(every) && evaluations[k].status == Status::Ok)
            .collect();
        let fine_keys: Vec<Key> = checked
            .iter()
            .map(|&k| Self::key(place, first + k, Fidelity::Fine))
            .collect();
        let fine_points: Vec<Vec<f64>> = checked.iter().map(|&k| points[k].clone()).collect();
        let fine = if checked.is_empty() {
            Vec::new()
        } else {
            self.evaluate_batch(&fine_keys, &fine_points, space, &coarse, seed)?
        };
        let summary = tally.fidelity.get_or_insert_with(FidelitySummary::default);
        summary.coarse += points.len();
        summary.fine_checks += checked.len();
        // The checks learn in the candidates' order, then the rest is corrected with all of
        // them: the same correction whatever order the simulations ended in.
        for (&k, fine) in checked.iter().zip(&fine) {
            let unit = self.unit_of(space, &points[k]);
            self.learn_from(&space.name, &evaluations[k], fine, &coarse, &unit, tally);
            evaluations[k] = merge_fine(&evaluations[k], fine, &coarse);
        }
        for (k, evaluation) in evaluations.iter_mut().enumerate() {
            if !checked.contains(&k) && evaluation.status == Status::Ok {
                let unit = self.unit_of(space, &points[k]);
                *evaluation = self.corrected(evaluation, &coarse, &unit, space);
            }
        }
        Ok(evaluations)
    }

    /// `values` in the unit cube of `space`'s bounds.
    fn unit_of(&self, space: &ModelSpace, values: &[f64]) -> Vec<f64> {
        values
            .iter()
            .zip(space.lower.iter().zip(&space.upper))
            .map(|(x, (l, u))| unit_cube::to_unit(*x, *l, *u))
            .collect()
    }

    /// Record how well the model's correction predicts the fine simulation `fine` of the
    /// coarse one `coarse` (experiments `experiments`, candidate at `unit`), then learn it.
    fn learn_from(
        &mut self,
        model: &str,
        coarse: &Evaluation,
        fine: &Evaluation,
        experiments: &[usize],
        unit: &[f64],
        tally: &mut Tally,
    ) {
        if fine.status != Status::Ok {
            return;
        }
        let campaign = self.campaign;
        let correction = self
            .corrections
            .entry(model.to_string())
            .or_insert_with(|| Correction::new(campaign.experiments.len()));
        let summary = tally.fidelity.get_or_insert_with(FidelitySummary::default);
        for &i in experiments {
            let (Some(Some(c)), Some(Some(f))) =
                (coarse.predictions.get(i), fine.predictions.get(i))
            else {
                continue;
            };
            let name = &campaign.file.experiments[i].file;
            let recording = &campaign.experiments[i].recording;
            summary
                .checks
                .push(correction.check(i, name, recording, unit, c, f));
            correction.learn(i, unit, c, f);
        }
    }

    /// The coarse evaluation `coarse` with the scores of `experiments` taken from their
    /// predictions corrected by the model's correction; the predictions stay the coarse
    /// simulation's (a later fine check of the candidate learns from them).
    fn corrected(
        &self,
        coarse: &Evaluation,
        experiments: &[usize],
        unit: &[f64],
        space: &ModelSpace,
    ) -> Evaluation {
        let mut corrected = coarse.clone();
        corrected.corrected = true;
        let Some(correction) = self.corrections.get(&space.name) else {
            return corrected;
        };
        for &i in experiments {
            let Some(Some(c)) = coarse.predictions.get(i) else {
                continue;
            };
            let predicted = correction.correct(i, unit, c);
            if let Some(slot) = corrected.scores.get_mut(i) {
                *slot = score(&self.campaign.experiments[i].recording, &predicted);
            }
        }
        if corrected
            .scores
            .iter()
            .zip(&coarse.scores)
            .any(|(a, b)| a.is_none() && b.is_some())
        {
            corrected.status = Status::Failed("non-finite corrected prediction".into());
        }
        corrected
    }

    /// Multi-fidelity, at the end of the search: if the best corrected candidate beats every
    /// simulated one, simulate it on the fine meshes (a fine check: it is learned from), so
    /// that the instance's best, the polish's start and its result are simulations.
    fn settle_best(&mut self, place: &Place<'_>, tally: &mut Tally) -> Result<(), CalibrateError> {
        let Some((candidate, value, index)) = tally.best_corrected.clone() else {
            return Ok(());
        };
        if tally.best.as_ref().is_some_and(|(_, b)| *b <= value) || index == usize::MAX {
            return Ok(());
        }
        let coarse = self.coarse_experiments(place);
        let key = Self::key(place, index, Fidelity::Fine);
        let fine = self
            .evaluate_batch(
                &[key],
                std::slice::from_ref(&candidate.values),
                place.space,
                &coarse,
                place.seed,
            )?
            .remove(0);
        // A corrected evaluation keeps its coarse simulation's predictions.
        let unit = self.unit_of(place.space, &candidate.values);
        self.learn_from(&place.space.name, &candidate, &fine, &coarse, &unit, tally);
        if let Some(summary) = tally.fidelity.as_mut() {
            summary.fine_checks += 1;
        }
        let merged = merge_fine(&candidate, &fine, &coarse);
        let merged_value = value_of(self.campaign, &merged, place.experiments);
        tally.offer(&merged, merged_value);
        Ok(())
    }

    /// Nelder-Mead polish from the best point, `polish` candidates one at a time.
    fn polish(
        &mut self,
        place: &Place<'_>,
        polish: usize,
        index: &mut usize,
        tally: &mut Tally,
        seen: &mut Vec<Evaluation>,
    ) -> Result<(), CalibrateError> {
        let Some((start, start_value)) = tally.best.as_ref().map(|(e, v)| (e.values.clone(), *v))
        else {
            return Ok(());
        };
        if polish == 0 {
            return Ok(());
        }
        let space = place.space;
        let bounds = space.lower.iter().zip(&space.upper);
        let unit: Vec<f64> = start
            .iter()
            .zip(bounds.clone())
            .map(|(x, (l, u))| unit_cube::to_unit(*x, *l, *u))
            .collect();
        let mut simplex = NelderMead::new(&unit, start_value, 0.05);
        for _ in 0..polish {
            if self.stop_at_noise_floor
                && self.at_noise_floor(tally, place.experiments, space.dimension())
            {
                break;
            }
            let point: Vec<f64> = simplex
                .ask()
                .iter()
                .zip(bounds.clone())
                .map(|(u, (l, h))| unit_cube::from_unit(*u, *l, *h))
                .collect();
            let value = self.score_one(place, index, &point, tally, seen)?;
            simplex.tell(value);
        }
        Ok(())
    }

    /// One optimisation instance on `experiments`. `warm` are earlier simulations of the same
    /// model (every fitted experiment scored): when given, the instance starts from them
    /// (told to the proposer, offered as its best) and runs `fold_budget` new simulations
    /// without polish. Every simulation it runs is appended to `seen`.
    #[allow(clippy::too_many_arguments)]
    fn instance(
        &mut self,
        space: &ModelSpace,
        fold: Option<&str>,
        experiments: &[usize],
        instance: usize,
        warm: &[Evaluation],
        seen: &mut Vec<Evaluation>,
    ) -> Result<InstanceResult, CalibrateError> {
        let seed = self
            .campaign
            .file
            .optimiser
            .seed
            .wrapping_add(instance as u64);
        // A warm-started fold runs its fresh simulations only: no polish, no finish.
        let warm_fold = self.fold_budget.is_some() && !warm.is_empty();
        let warm: Vec<(&Evaluation, Option<f64>)> = if warm_fold {
            warm.iter()
                .map(|e| (e, value_of(self.campaign, e, experiments)))
                .collect()
        } else {
            Vec::new()
        };
        let (budget, polish, least_squares) = match self.fold_budget {
            Some(fresh) if warm_fold => (fresh, 0, 0),
            _ => (self.budget, self.polish, self.least_squares),
        };
        let mut proposer = (self.factory)(space, warm.len() + budget, self.batch, seed);
        let mut tally = Tally::default();
        if !warm.is_empty() {
            let points: Vec<Vec<f64>> = warm.iter().map(|(e, _)| e.values.clone()).collect();
            let values: Vec<Option<f64>> = warm
                .iter()
                .map(|(_, v)| v.map(|e| libm::log(e.max(1e-300))))
                .collect();
            proposer
                .tell(&points, &values)
                .map_err(CalibrateError::Optimiser)?;
            for (evaluation, value) in &warm {
                tally.offer(evaluation, *value);
            }
        }
        // The total counts the polish from the start, so a bar never runs past it; the
        // instance is announced before its initial design runs.
        let total = budget + polish + usize::from(least_squares > 0);
        let place = Place {
            space,
            fold,
            instance,
            experiments,
            seed,
            total,
        };
        (self.progress)(&space.name, fold, instance, 0, total, None);
        let mut index = 0;
        self.propose(
            &place,
            proposer.as_mut(),
            budget,
            &mut index,
            &mut tally,
            seen,
        )?;
        self.settle_best(&place, &mut tally)?;
        self.polish(&place, polish, &mut index, &mut tally, seen)?;
        // Least-squares finish from the best point: the diagnosis' bounded Levenberg-Marquardt
        // on the whitened residuals (its simulations logged beside the calibration's), its
        // result then scored as a candidate like any other.
        if let (Some(start), true) = (
            tally.best.as_ref().map(|(e, _)| e.values.clone()),
            least_squares > 0,
        ) {
            if let Some(finished) = self.least_squares_finish(
                space,
                fold,
                instance,
                experiments,
                &start,
                least_squares,
            )? {
                self.score_one(&place, &mut index, &finished, &mut tally, seen)?;
            }
        }
        let Tally {
            best,
            best_corrected: _,
            fidelity,
            history,
            simulated,
            failed,
            infeasible,
            first_failure,
        } = tally;
        let Some((best, fit_error)) = best else {
            return Err(CalibrateError::NoFeasibleCandidate(
                space.name.clone(),
                first_failure,
            ));
        };
        Ok(InstanceResult {
            model: space.name.clone(),
            fold: fold.map(str::to_string),
            instance,
            seed,
            best,
            fit_error,
            history,
            simulated,
            failed,
            infeasible,
            first_rejection: first_failure,
            fidelity,
        })
    }
}

/// A candidate's total error over `experiments`; `None` unless it simulated.
fn value_of(campaign: &Campaign, evaluation: &Evaluation, experiments: &[usize]) -> Option<f64> {
    if evaluation.status == Status::Ok {
        evaluation.total(campaign, experiments)
    } else {
        None
    }
}

/// The finalists of one model so far: its instances, each fold's best re-scored on every
/// experiment, and every simulation its all-experiment instances ran (the warm start of
/// its folds).
struct ModelRun {
    space: ModelSpace,
    instances: Vec<InstanceResult>,
    finalists: Vec<(Option<String>, Evaluation)>,
    seen: Vec<Evaluation>,
}

/// Run the campaign: every model's instances on the fitted experiments, then leave-one-out
/// folds (for every model, or only for the selected model), the
/// simulations through `executor`. Results go to `output/simulations.jsonl` as they arrive.
pub fn calibrate<'a>(
    campaign: &'a Campaign,
    output: &Path,
    options: &RunOptions,
    executor: &'a mut dyn Executor,
    factory: &'a ProposerFactory<'a>,
    progress: &'a mut Progress<'a>,
) -> Result<Calibration, CalibrateError> {
    let optimiser = &campaign.file.optimiser;
    let log = SimulationLog::open(&output.join("simulations.jsonl"))?;
    let sizes = super::cost::Sizes::of(campaign, options);
    let mut runner = Runner {
        campaign,
        log,
        executor,
        factory,
        progress,
        budget: sizes.budget,
        batch: optimiser.parallel,
        polish: sizes.polish,
        least_squares: options
            .least_squares
            .or(optimiser.least_squares)
            .unwrap_or(0),
        stop_at_noise_floor: optimiser.stop_at_noise_floor,
        fold_budget: optimiser.fold_budget,
        output: output.to_path_buf(),
        corrections: BTreeMap::new(),
    };
    let instances = options.instances.unwrap_or(optimiser.instances);
    let leave_one_out = options.leave_one_out.unwrap_or(optimiser.leave_one_out);
    let fitted = campaign.fitted();
    let holdouts: Vec<usize> = (0..campaign.experiments.len())
        .filter(|i| !fitted.contains(i))
        .collect();
    // Model selection: every model on every fitted experiment.
    let mut runs = Vec::new();
    for model in &campaign.file.models {
        let space = campaign.space(model);
        let mut run = ModelRun {
            space,
            instances: Vec::new(),
            finalists: Vec::new(),
            seen: Vec::new(),
        };
        runner.fold(&mut run, None, &fitted, instances)?;
        runs.push(run);
    }
    // Leave-one-out: fit on n-1, score the fold's best on all n (seed 000 sec. 4.2), for
    // every model or for the selected one: the model whose calibrated constants the report
    // recommends (held-out prediction, a margin inside the noise decided by the information
    // criterion; `fit::result::recommend`). A fold's best, scored on all n, joins its model's
    // finalists and becomes the model's constants if it fits better; that can move the
    // selection to another model (a better fit that predicts the held-out tests worse), whose
    // folds then run too, so the model recommended at the end is the one validated.
    // The selection is made once at the start and again after each round of folds (only
    // the folds change the finalists), so the loop ends with the final one.
    let mut selected_model = select_model(&runs, campaign, &fitted);
    if fitted.len() > 1 {
        let mut folded = vec![false; runs.len()];
        loop {
            let wanted: Vec<usize> = (0..runs.len())
                .filter(|&k| {
                    !folded[k]
                        && match leave_one_out {
                            LeaveOneOut::Off => false,
                            LeaveOneOut::Every => true,
                            LeaveOneOut::Selected => selected_model == Some(k),
                        }
                })
                .collect();
            if wanted.is_empty() {
                break;
            }
            for k in wanted {
                for &left in &fitted {
                    let rest: Vec<usize> = fitted.iter().copied().filter(|&i| i != left).collect();
                    let fold = campaign.file.experiments[left].file.clone();
                    runner.fold(&mut runs[k], Some(fold), &rest, instances)?;
                }
                folded[k] = true;
            }
            selected_model = select_model(&runs, campaign, &fitted);
        }
    }
    let mut results = Vec::new();
    let mut searched = Vec::new();
    let mut wants_intervals = Vec::new();
    for (k, run) in runs.into_iter().enumerate() {
        wants_intervals.push(match optimiser.uncertainty {
            UncertaintyFor::Every => true,
            UncertaintyFor::Selected => selected_model == Some(k),
            UncertaintyFor::None => false,
        });
        let (result, seen) = runner.conclude(run, &fitted, &holdouts)?;
        results.push(result);
        searched.push(seen);
    }
    let simulated = after_search(
        campaign,
        &mut results,
        &searched,
        &wants_intervals,
        options.outcomes,
    );
    Ok(Calibration { results, simulated })
}

/// A calibration's results, and (if asked for, [`RunOptions::outcomes`]) the simulations
/// of its selected and starting constants that the report draws.
pub struct Calibration {
    /// One result per model, in the campaign's order.
    pub results: Vec<ModelResult>,
    /// The report's simulations (`None` unless asked for).
    pub simulated: Option<Simulated>,
}

/// Every model's selected constants simulated on every campaign experiment, and its starting
/// constants on the held-out ones (the report's overlays, histograms and validity range);
/// `None` where a simulation failed or was not wanted. Indexed `[model][experiment]`.
pub struct Simulated {
    /// The selected constants' outcomes.
    pub selected: Vec<Vec<Option<Outcome>>>,
    /// The starting constants' outcomes on the held-out experiments (`None` elsewhere).
    pub starting: Vec<Vec<Option<Outcome>>>,
}

/// What a job of [`after_search`] is for.
#[derive(Clone, Copy)]
enum AfterSearch {
    /// Model `k`'s selected constants: the report's overlay and the forward differences'
    /// base point.
    Selected(usize),
    /// Model `k`'s starting constants on a held-out experiment: the report's comparison.
    Starting(usize),
    /// Model `k`'s forward-difference point `i` (1-based: constant `i - 1` stepped).
    Stepped(usize, usize),
}

/// What a job of [`after_search`] keeps: the whole outcome for the report, the predictions
/// alone for a forward difference.
enum Kept {
    Whole(Box<Outcome>),
    Predicted(Result<Vec<f64>, String>),
}

/// After the searches: the linearised intervals and posterior of the models in `intervals`
/// (their forward differences about the selected constants) and, if `outcomes`, the report's
/// simulations, all in one pool of simulations (`fit::outcomes`), so that the selected
/// constants' simulations serve both and the cores stay busy to the last simulation.
/// `searched` is each model's logged candidates (the intervals are held against them).
fn after_search(
    campaign: &Campaign,
    results: &mut [ModelResult],
    searched: &[Vec<Evaluation>],
    intervals: &[bool],
    outcomes: bool,
) -> Option<Simulated> {
    use crate::fit::outcomes::{simulate_all, Job};
    use crate::fit::uncertainty::{
        against_search, difference_points, finite_predictions, from_linearisation, Linearisation,
    };
    let experiments = campaign.experiments.len();
    let all: Vec<usize> = (0..experiments).collect();
    let fitted = campaign.fitted();
    let spaces: Vec<Option<ModelSpace>> = results
        .iter()
        .map(|r| campaign.model(&r.model).map(|m| campaign.space(m)))
        .collect();
    let points: Vec<Vec<Vec<f64>>> = results
        .iter()
        .zip(&spaces)
        .zip(intervals)
        .map(|((result, space), &wanted)| match space {
            Some(space) if wanted => difference_points(space, &result.selected.values),
            _ => Vec::new(),
        })
        .collect();
    let mut jobs: Vec<(AfterSearch, Job<'_>)> = Vec::new();
    for (k, (result, space)) in results.iter().zip(&spaces).enumerate() {
        let Some(space) = space else { continue };
        if outcomes || !points[k].is_empty() {
            let values = &result.selected.values;
            for &experiment in &all {
                let job = Job {
                    space,
                    values,
                    experiment,
                };
                jobs.push((AfterSearch::Selected(k), job));
            }
        }
        for (i, values) in points[k].iter().enumerate().skip(1) {
            for &experiment in &all {
                let job = Job {
                    space,
                    values,
                    experiment,
                };
                jobs.push((AfterSearch::Stepped(k, i), job));
            }
        }
        if let (true, Some(baseline)) = (outcomes, &result.baseline) {
            let values = &baseline.evaluation.values;
            for &experiment in &all {
                if campaign.file.experiments[experiment].holdout {
                    let job = Job {
                        space,
                        values,
                        experiment,
                    };
                    jobs.push((AfterSearch::Starting(k), job));
                }
            }
        }
    }
    let only_jobs: Vec<Job<'_>> = jobs.iter().map(|(_, job)| *job).collect();
    let done = simulate_all(campaign, &only_jobs, |n, outcome| match jobs[n].0 {
        AfterSearch::Stepped(..) => {
            Kept::Predicted(finite_predictions(campaign, jobs[n].1.experiment, &outcome))
        }
        _ => Kept::Whole(Box::new(outcome)),
    });
    // The simulations by model, purpose, point and experiment.
    let empty = || -> Vec<Vec<Option<Result<Outcome, String>>>> {
        (0..results.len())
            .map(|_| (0..experiments).map(|_| None).collect())
            .collect()
    };
    let (mut selected, mut starting) = (empty(), empty());
    let mut stepped: BTreeMap<(usize, usize, usize), Result<Vec<f64>, String>> = BTreeMap::new();
    for ((purpose, job), result) in jobs.iter().zip(done) {
        let e = job.experiment;
        match (*purpose, result) {
            (AfterSearch::Selected(k), Ok(Kept::Whole(outcome))) => {
                selected[k][e] = Some(Ok(*outcome))
            }
            (AfterSearch::Starting(k), Ok(Kept::Whole(outcome))) => {
                starting[k][e] = Some(Ok(*outcome))
            }
            (AfterSearch::Selected(k), Err(error)) => selected[k][e] = Some(Err(error)),
            (AfterSearch::Stepped(k, i), Ok(Kept::Predicted(predicted))) => {
                stepped.insert((k, i, e), predicted);
            }
            (AfterSearch::Stepped(k, i), Err(error)) => {
                stepped.insert((k, i, e), Err(error));
            }
            _ => {}
        }
    }
    for (k, result) in results.iter_mut().enumerate() {
        let Some(space) = &spaces[k] else { continue };
        if points[k].is_empty() {
            continue;
        }
        let predicted = |on: &[usize], i: usize, e: usize| -> Result<Vec<f64>, String> {
            let experiment = on[e];
            let missing = || {
                Err(format!(
                    "{}: not simulated",
                    campaign.experiments[experiment].file.name
                ))
            };
            if i == 0 {
                match &selected[k][experiment] {
                    Some(Ok(outcome)) => finite_predictions(campaign, experiment, outcome),
                    Some(Err(error)) => Err(error.clone()),
                    None => missing(),
                }
            } else {
                stepped
                    .get(&(k, i, experiment))
                    .cloned()
                    .unwrap_or_else(missing)
            }
        };
        // On every experiment (the held-out ones get their bands), else on the fitted ones.
        let linearisation =
            Linearisation::assemble(campaign, &points[k], &all, |i, e| predicted(&all, i, e))
                .or_else(|_| {
                    Linearisation::assemble(campaign, &points[k], &fitted, |i, e| {
                        predicted(&fitted, i, e)
                    })
                });
        let Ok(linearisation) = linearisation else {
            continue;
        };
        result.uncertainty = from_linearisation(campaign, &linearisation, &fitted)
            .ok()
            .map(|mut uncertainty| {
                uncertainty.search_check = against_search(
                    campaign,
                    &linearisation,
                    &uncertainty,
                    &result.selected,
                    &searched[k],
                    &fitted,
                );
                uncertainty
            });
        result.posterior = crate::fit::posterior::sample(
            campaign,
            space,
            &linearisation,
            &fitted,
            campaign.file.optimiser.seed,
        )
        .ok();
    }
    let kept = |rows: Vec<Vec<Option<Result<Outcome, String>>>>| -> Vec<Vec<Option<Outcome>>> {
        rows.into_iter()
            .map(|row| row.into_iter().map(|o| o.and_then(Result::ok)).collect())
            .collect()
    };
    outcomes.then(|| Simulated {
        selected: kept(selected),
        starting: kept(starting),
    })
}

/// A model's constants: the finalist (the best of a fold's instances, scored on every
/// experiment) with the lowest error over `fitted`, and that error.
fn best_finalist<'r>(
    run: &'r ModelRun,
    campaign: &Campaign,
    fitted: &[usize],
) -> Option<(&'r Evaluation, f64)> {
    run.finalists
        .iter()
        .filter_map(|(_, e)| e.total(campaign, fitted).map(|t| (e, t)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// The model the report will recommend among `runs` as they stand
/// (`fit::result::selected_model` on each model's [`best_finalist`]).
fn select_model(runs: &[ModelRun], campaign: &Campaign, fitted: &[usize]) -> Option<usize> {
    let sets: Vec<crate::fit::result::SetScore> = runs
        .iter()
        .filter_map(|run| {
            let (constants, _) = best_finalist(run, campaign, fitted)?;
            let at_bounds = constants_at_bounds(&run.space, &constants.values).len();
            crate::fit::result::SetScore::of(&run.space.name, false, constants, campaign, at_bounds)
        })
        .collect();
    let name = crate::fit::result::selected_model(&sets)?;
    runs.iter().position(|run| run.space.name == name)
}

impl Runner<'_> {
    /// Run one fold's instances on `experiments` and add its best, scored on every
    /// experiment, to the model's finalists. The all-experiment fold (`None`) records its
    /// simulations as the warm start of the later folds.
    fn fold(
        &mut self,
        run: &mut ModelRun,
        fold: Option<String>,
        experiments: &[usize],
        instances: usize,
    ) -> Result<(), CalibrateError> {
        let all: Vec<usize> = (0..self.campaign.experiments.len()).collect();
        let warm: &[Evaluation] = if fold.is_some() { &run.seen } else { &[] };
        let mut seen = Vec::new();
        let mut fold_results = Vec::new();
        for instance in 0..instances {
            fold_results.push(self.instance(
                &run.space,
                fold.as_deref(),
                experiments,
                instance,
                warm,
                &mut seen,
            )?);
        }
        if fold.is_none() {
            run.seen = seen;
        }
        // The fold's best, re-scored on every experiment (seed 000's LOO protocol): only
        // the experiments it was not simulated on run again (simulations are deterministic
        // in the constants, so the scores it has stand).
        let winner = fold_results
            .iter()
            .min_by(|a, b| a.fit_error.total_cmp(&b.fit_error))
            .cloned();
        run.instances.extend(fold_results);
        if let Some(winner) = winner {
            let missing: Vec<usize> = all
                .iter()
                .copied()
                .filter(|&i| winner.best.scores.get(i).is_none_or(|s| s.is_none()))
                .collect();
            let scored = if missing.is_empty() || winner.best.status != Status::Ok {
                winner.best.clone()
            } else {
                let key = Key {
                    model: run.space.name.clone(),
                    fold: Some(format!("final:{}", fold.clone().unwrap_or_default())),
                    instance: winner.instance,
                    index: 0,
                    fidelity: Default::default(),
                };
                let rest = self
                    .evaluate_batch(
                        &[key],
                        std::slice::from_ref(&winner.best.values),
                        &run.space,
                        &missing,
                        winner.seed,
                    )?
                    .into_iter()
                    .next();
                match rest {
                    Some(rest) => merge_scores(&winner.best, &rest, &missing),
                    None => winner.best.clone(),
                }
            };
            run.finalists.push((fold, scored));
        }
        Ok(())
    }

    /// The model's result: the finalist with the lowest fitted error, its held-out error, the
    /// starting constants scored as a baseline and constants at bounds (the uncertainty is
    /// [`after_search`]'s); with the candidates the search logged.
    fn conclude(
        &mut self,
        run: ModelRun,
        fitted: &[usize],
        holdouts: &[usize],
    ) -> Result<(ModelResult, Vec<Evaluation>), CalibrateError> {
        let campaign = self.campaign;
        let all: Vec<usize> = (0..campaign.experiments.len()).collect();
        let (selected, fit_error) = best_finalist(&run, campaign, fitted)
            .map(|(e, t)| (e.clone(), t))
            .ok_or_else(|| CalibrateError::NoFeasibleCandidate(run.space.name.clone(), None))?;
        let space = run.space;
        let holdout_error = if holdouts.is_empty() {
            None
        } else {
            selected.total(campaign, holdouts)
        };
        // The starting constants, scored on every experiment like a finalist.
        let baseline = match space.starting_values(&campaign.base) {
            Some(values) => {
                let key = Key {
                    model: space.name.clone(),
                    fold: Some("baseline".into()),
                    instance: 0,
                    index: 0,
                    fidelity: Default::default(),
                };
                let evaluation = self
                    .evaluate_batch(&[key], std::slice::from_ref(&values), &space, &all, 0)?
                    .into_iter()
                    .next();
                evaluation.map(|evaluation| Baseline {
                    fit_error: evaluation.total(campaign, fitted),
                    holdout_error: if holdouts.is_empty() {
                        None
                    } else {
                        evaluation.total(campaign, holdouts)
                    },
                    evaluation,
                })
            }
            None => None,
        };
        let at_bounds = constants_at_bounds(&space, &selected.values);
        let mut constants: Vec<NamedConstant> = space
            .names
            .iter()
            .zip(&selected.values)
            .zip(space.units(&campaign.base))
            .map(|((name, value), unit)| NamedConstant {
                name: name.clone(),
                value: *value,
                unit: unit.to_string(),
            })
            .collect();
        let setup = constants.split_off(space.constant_count());
        Ok((
            ModelResult {
                uncertainty: None,
                posterior: None,
                baseline,
                at_bounds,
                constants,
                setup,
                model: space.name.clone(),
                instances: run.instances,
                finalists: run.finalists,
                selected,
                fit_error,
                holdout_error,
            },
            run.seen,
        ))
    }
}

/// The coarse evaluation `coarse` with the scores and predictions of `experiments` taken from
/// their fine simulation `fine`: the candidate simulated on the fine meshes throughout (the
/// other experiments have one mesh); failed if the fine simulation failed.
fn merge_fine(coarse: &Evaluation, fine: &Evaluation, experiments: &[usize]) -> Evaluation {
    let mut merged = merge_scores(coarse, fine, experiments);
    merged.fidelity = Fidelity::Fine;
    merged.corrected = false;
    for &i in experiments {
        if let (Some(slot), Some(prediction)) =
            (merged.predictions.get_mut(i), fine.predictions.get(i))
        {
            slot.clone_from(prediction);
        }
    }
    merged
}

/// `base` with the scores of the experiments `missing` taken from `rest` (the same constants
/// simulated on those experiments only); failed if either failed.
fn merge_scores(base: &Evaluation, rest: &Evaluation, missing: &[usize]) -> Evaluation {
    let mut merged = base.clone();
    for &i in missing {
        if let (Some(slot), Some(score)) = (merged.scores.get_mut(i), rest.scores.get(i)) {
            *slot = *score;
        }
    }
    merged.wall_time += rest.wall_time;
    if rest.status != Status::Ok {
        merged.status = rest.status.clone();
    }
    merged
}
