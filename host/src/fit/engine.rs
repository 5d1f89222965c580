//! Runs the simulations of a least-squares fit (the diagnosis, the calibration's finish):
//! batches of candidate constants handed to an [`Executor`] (this machine's pool or Slurm, the
//! same executor a calibration uses), every result appended to the [`Journal`]
//! (`diagnosis.jsonl`, `least-squares-*.jsonl`) as it ends, with where it was computed; a rerun
//! over the same folder replays the log instead of simulating again, so a killed diagnosis
//! loses nothing.
//!
//! A log entry is keyed by a 64-bit FNV-1a hash of everything that determines the simulation:
//! the realised material file, the anvil friction, the lagged-rate mixture and the experiment
//! file; a changed calibration therefore never reuses stale results.

use super::campaign::Campaign;
use super::executor::{
    Executor, ExecutorError, Origin, Prediction, PredictionBatch, PredictionJob,
};
use super::hypothesis::{Hypothesis, Realisation};
use super::FitError;
use crate::experiment::Experiment;
use crate::hash::fnv1a;
use crate::journal::Journal;
use crate::solver::SolverSettings;
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
    /// Where and by which stoss binary it was computed (absent in journals written before
    /// the engine ran through the executors, and for a hypothesis that could not be
    /// realised).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    origin: Option<Origin>,
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
    /// The campaign whose experiments are simulated.
    pub campaign: &'a Campaign,
    /// The experiments simulated (the campaign's, in its order).
    pub experiments: &'a [Experiment],
    /// Where stages and simulation counts are reported.
    progress: &'a mut dyn FnMut(Progress<'_>),
    executor: &'a mut dyn Executor,
    settings: SolverSettings,
    known: HashMap<String, Prediction>,
    log: Option<Journal>,
    /// Points (sets of constants) evaluated, fresh or replayed.
    pub points: usize,
    /// Experiment simulations run (fresh).
    pub simulated: usize,
    /// Experiment simulations replayed from the log.
    pub replayed: usize,
}

impl<'a> Engine<'a> {
    /// An engine simulating `campaign`'s experiments through `executor`, logging to `log`
    /// (replaying what it already holds).
    pub fn new(
        campaign: &'a Campaign,
        executor: &'a mut dyn Executor,
        log: Option<&Path>,
        progress: &'a mut dyn FnMut(Progress<'_>),
    ) -> Result<Self, FitError> {
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
            campaign,
            experiments: &campaign.experiments,
            progress,
            executor,
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

    /// The journal key of simulating `experiment` with `realisation` (`None`: the
    /// hypothesis could not be realised at these constants).
    fn key(&self, realisation: Option<&Realisation>, experiment: usize) -> String {
        let realised = realisation.map(|r| {
            (
                toml::to_string(&r.file).unwrap_or_default(),
                r.anvil_friction.map(f64::to_bits),
                r.lagged_mixture.to_bits(),
            )
        });
        // The set-up parameters enter the key only when there are any, so that journals
        // written before they existed keep their keys.
        let setup = realisation
            .filter(|r| !r.setup.is_empty())
            .map(|r| format!("|{:?}", r.setup))
            .unwrap_or_default();
        let text = format!(
            "{realised:?}|{}|{:?}{setup}",
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

    /// Simulate each job `(constants, experiment)` once, through the executor; results in job
    /// order. A job already in the journal is replayed; one whose hypothesis cannot be realised
    /// at its constants is a failed prediction (journalled, not simulated).
    pub fn run(
        &mut self,
        hypothesis: &Hypothesis,
        jobs: &[(&[f64], usize)],
    ) -> Result<Vec<Prediction>, FitError> {
        // Each job realised once: its key is read from the realisation it then runs.
        let realised: Vec<Result<Realisation, String>> = jobs
            .iter()
            .map(|(values, _)| hypothesis.realise(values))
            .collect();
        let keys: Vec<String> = realised
            .iter()
            .zip(jobs)
            .map(|(r, (_, e))| self.key(r.as_ref().ok(), *e))
            .collect();
        let mut results: Vec<Option<Prediction>> = vec![None; jobs.len()];
        let mut realisations: Vec<(usize, Realisation)> = Vec::new();
        for (index, (realisation, key)) in realised.into_iter().zip(&keys).enumerate() {
            if let Some(known) = self.known.get(key) {
                self.replayed += 1;
                results[index] = Some(known.clone());
                continue;
            }
            match realisation {
                Ok(realisation) => realisations.push((index, realisation)),
                Err(message) => {
                    let failed: Prediction = Err(message);
                    append(self.log.as_mut(), key, &failed, None)?;
                    self.simulated += 1;
                    self.known.insert(key.clone(), failed.clone());
                    results[index] = Some(failed);
                }
            }
        }
        if !realisations.is_empty() {
            // A stop requested before new simulations start: none is started.
            super::interrupt::check()?;
            let batch = PredictionBatch {
                campaign: self.campaign,
                jobs: realisations
                    .iter()
                    .map(|(index, realisation)| PredictionJob {
                        key: &keys[*index],
                        realisation,
                        experiment: jobs[*index].1,
                    })
                    .collect(),
            };
            // Each new simulation is appended to the journal as soon as it finishes.
            let journal = std::sync::Mutex::new(&mut self.log);
            let record = |at: usize, prediction: &Prediction, origin: &Origin| {
                let mut journal = journal
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner);
                append(
                    journal.as_mut(),
                    batch.jobs[at].key,
                    prediction,
                    Some(origin),
                )
                .map_err(|e| ExecutorError::Executor(e.to_string()))
            };
            let predictions = self.executor.predict(&batch, &record)?;
            // A stop requested while the batch ran: it is journalled; nothing after it starts.
            super::interrupt::check()?;
            if predictions.len() != realisations.len() {
                return Err(FitError::Simulation(format!(
                    "the executor returned {} predictions for {} jobs",
                    predictions.len(),
                    realisations.len()
                )));
            }
            for (&(index, _), prediction) in realisations.iter().zip(predictions) {
                self.simulated += 1;
                self.known.insert(keys[index].clone(), prediction.clone());
                results[index] = Some(prediction);
            }
        }
        (self.progress)(Progress::Simulations {
            run: self.simulated,
            replayed: self.replayed,
        });
        Ok(results.into_iter().flatten().collect())
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

/// Append one simulation's result to the journal, if there is one.
fn append(
    journal: Option<&mut Journal>,
    key: &str,
    result: &Prediction,
    origin: Option<&Origin>,
) -> Result<(), FitError> {
    let Some(journal) = journal else {
        return Ok(());
    };
    let entry = LogEntry {
        key: key.into(),
        predicted: result.as_ref().ok().cloned(),
        error: result.as_ref().err().cloned(),
        origin: origin.cloned(),
    };
    journal
        .append(&entry)
        .map_err(|e| FitError::Io(format!("{}: {e}", journal.path().display())))
}
