//! Runs the simulations of a least-squares fit (the diagnosis, the calibration's finish): batches of candidate constants in parallel (one
//! thread per simulation, so results do not depend on the thread count), every result appended
//! to the [`Journal`] `diagnosis.jsonl` as it ends; a rerun over the same folder replays the log
//! instead of simulating again, so a killed diagnosis loses nothing.
//!
//! A log entry is keyed by a 64-bit FNV-1a hash of everything that determines the simulation:
//! the realised material file, the anvil friction, the lagged-rate mixture and the experiment
//! file; a changed calibration therefore never reuses stale results.

use super::hypothesis::Hypothesis;
use super::FitError;
use crate::experiment::Experiment;
use crate::hash::fnv1a;
use crate::journal::Journal;
use crate::solver::SolverSettings;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::path::Path;

/// Predictions of each requested experiment, or why the simulation failed.
pub type Predictions = Result<Vec<Vec<f64>>, String>;

#[derive(Serialize, Deserialize)]
struct LogEntry {
    key: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    predicted: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    error: Option<String>,
}

/// What a diagnosis reports while it runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Progress<'s> {
    /// A stage begins (refit, locate, score tests, refit with a term...).
    Stage(&'s str),
    /// A batch of simulations ended: the totals so far, run and replayed from the log.
    Simulations {
        /// Simulations run.
        run: usize,
        /// Simulations replayed from the log.
        replayed: usize,
    },
}

/// The simulation engine of one diagnosis or least-squares fit.
pub struct Engine<'a> {
    /// The experiments simulated (a campaign's, in its order).
    pub experiments: &'a [Experiment],
    /// Where stages and simulation counts are reported.
    progress: &'a mut dyn FnMut(Progress<'_>),
    pool: rayon::ThreadPool,
    settings: SolverSettings,
    known: HashMap<String, Result<Vec<f64>, String>>,
    log: Option<Journal>,
    /// Points (sets of constants) evaluated, fresh or replayed.
    pub points: usize,
    /// Experiment simulations run (fresh).
    pub simulated: usize,
    /// Experiment simulations replayed from the log.
    pub replayed: usize,
}

impl<'a> Engine<'a> {
    /// An engine with `parallel` simulations at once, logging to `log` (replaying what it
    /// already holds).
    pub fn new(
        experiments: &'a [Experiment],
        parallel: usize,
        log: Option<&Path>,
        progress: &'a mut dyn FnMut(Progress<'_>),
    ) -> Result<Self, FitError> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(parallel.max(1))
            .build()
            .map_err(|e| FitError::Threads(e.to_string()))?;
        let mut known = HashMap::new();
        let log = match log {
            None => None,
            Some(path) => {
                let (journal, lines) = Journal::open(path)
                    .map_err(|e| FitError::Io(format!("{}: {e}", path.display())))?;
                for (index, line) in lines.iter().enumerate() {
                    let entry: LogEntry = serde_json::from_str(line).map_err(|e| {
                        FitError::Io(format!("{}:{}: {e}", path.display(), index + 1))
                    })?;
                    let value = match (entry.predicted, entry.error) {
                        (Some(p), _) => Ok(p),
                        (None, Some(e)) => Err(e),
                        (None, None) => continue,
                    };
                    known.insert(entry.key, value);
                }
                Some(journal)
            }
        };
        Ok(Self {
            experiments,
            progress,
            pool,
            settings: SolverSettings {
                threads: Some(1),
                ..SolverSettings::default()
            },
            known,
            log,
            points: 0,
            simulated: 0,
            replayed: 0,
        })
    }

    fn key(&self, hypothesis: &Hypothesis, values: &[f64], experiment: usize) -> String {
        let realised = hypothesis.realise(values).ok().map(|r| {
            (
                toml::to_string(&r.file).unwrap_or_default(),
                r.anvil_friction.map(f64::to_bits),
                r.lagged_mixture.to_bits(),
            )
        });
        let text = format!(
            "{realised:?}|{}|{:?}",
            self.experiments[experiment].path.display(),
            self.experiments[experiment].file.setup
        );
        format!("{:016x}", fnv1a(&text))
    }

    /// Simulate `experiments` at every point of `points` (constants of `hypothesis`).
    pub fn predict(
        &mut self,
        hypothesis: &Hypothesis,
        points: &[Vec<f64>],
        experiments: &[usize],
    ) -> Result<Vec<Predictions>, FitError> {
        self.points += points.len();
        let jobs: Vec<(&[f64], usize)> = points
            .iter()
            .flat_map(|values| experiments.iter().map(move |&e| (values.as_slice(), e)))
            .collect();
        let results = self.run(hypothesis, &jobs)?;
        let mut per_point = Vec::with_capacity(points.len());
        for chunk in results.chunks(experiments.len().max(1)) {
            per_point.push(chunk.iter().cloned().collect::<Result<Vec<_>, _>>());
        }
        per_point.resize(points.len(), Ok(Vec::new()));
        Ok(per_point)
    }

    /// Simulate each job `(constants, experiment)` once, in parallel; results in job order.
    pub fn run(
        &mut self,
        hypothesis: &Hypothesis,
        jobs: &[(&[f64], usize)],
    ) -> Result<Vec<Result<Vec<f64>, String>>, FitError> {
        let keys: Vec<String> = jobs
            .iter()
            .map(|(values, e)| self.key(hypothesis, values, *e))
            .collect();
        let experiments = self.experiments;
        let settings = &self.settings;
        let known = &self.known;
        // Each new simulation is appended to the journal as soon as it finishes.
        let journal = std::sync::Mutex::new(&mut self.log);
        let fresh: Vec<Option<Result<Prediction, FitError>>> = self.pool.install(|| {
            jobs.par_iter()
                .zip(&keys)
                .map(|((values, e), key)| {
                    if known.contains_key(key) {
                        return None;
                    }
                    let result = hypothesis
                        .realise(values)
                        .and_then(|r| r.predict(&experiments[*e], settings));
                    let mut journal = journal
                        .lock()
                        .unwrap_or_else(std::sync::PoisonError::into_inner);
                    Some(append(journal.as_mut(), key, &result).map(|()| result))
                })
                .collect()
        });
        let mut results = Vec::with_capacity(jobs.len());
        for (key, new) in keys.iter().zip(fresh) {
            let result = match new {
                Some(result) => {
                    let result = result?;
                    self.simulated += 1;
                    self.known.insert(key.clone(), result.clone());
                    result
                }
                None => {
                    self.replayed += 1;
                    self.known[key].clone()
                }
            };
            results.push(result);
        }
        (self.progress)(Progress::Simulations {
            run: self.simulated,
            replayed: self.replayed,
        });
        Ok(results)
    }

    /// Report the start of a stage.
    pub fn stage(&mut self, name: &str) {
        (self.progress)(Progress::Stage(name));
    }

    /// Whitened residuals `(predicted - recorded) / uncertainty` of `experiments`,
    /// concatenated in order.
    pub fn whiten(&self, experiments: &[usize], predictions: &[Vec<f64>]) -> Vec<f64> {
        experiments
            .iter()
            .zip(predictions)
            .flat_map(|(&e, predicted)| {
                self.experiments[e]
                    .recording
                    .iter()
                    .zip(predicted)
                    .map(|(point, p)| (p - point.value) / point.uncertainty)
            })
            .collect()
    }

    /// The solver settings of the engine's simulations.
    pub fn settings(&self) -> &SolverSettings {
        &self.settings
    }
}

/// A simulation's predictions, or why it failed.
type Prediction = Result<Vec<f64>, String>;

/// Append one simulation's result to the journal, if there is one.
fn append(journal: Option<&mut Journal>, key: &str, result: &Prediction) -> Result<(), FitError> {
    let Some(journal) = journal else {
        return Ok(());
    };
    let entry = LogEntry {
        key: key.into(),
        predicted: result.as_ref().ok().cloned(),
        error: result.as_ref().err().cloned(),
    };
    journal
        .append(&entry)
        .map_err(|e| FitError::Io(format!("{}: {e}", journal.path().display())))
}
