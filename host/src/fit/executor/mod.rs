//! Executors: where simulations run. Two kinds of work go through the same executor:
//! - the candidates of an optimiser batch ([`Executor::evaluate`]: a model's constants, scored
//!   on a campaign's experiments);
//! - the prediction jobs of a least-squares fit ([`Executor::predict`]: a realised hypothesis,
//!   one experiment, its predictions), as the diagnosis' refits and the calibration's
//!   least-squares finish run them.
//!
//! `local` runs them on this machine's cores; `slurm` runs each as a task of a Slurm cluster
//! (`slurm.rs`), a `stoss evaluate` process that reads a task file and writes a result file
//! (`task.rs`).
//!
//! Every executor hands each evaluation to the coordinator as soon as it ends (the coordinator
//! appends it to the simulation log, so `--resume` works the same for all) and returns the
//! batch in the order it was asked. An evaluation depends only on the campaign and the
//! candidate, never on where or in which order it ran, so every executor gives the same
//! calibration.

pub mod settings;
pub mod slurm;
pub mod task;

pub use settings::{ExecutorEntry, ExecutorKind, SlurmMode};
pub use task::Origin;

use super::campaign::Campaign;
use super::fidelity::Fidelity;
use super::hypothesis::Realisation;
use super::log::Key;
use super::log::LogError;
use super::objective::{evaluate_at, Evaluation};
use crate::fit::ModelSpace;
use crate::solver::SolverSettings;
use rayon::prelude::*;

/// Why an executor could not return a batch.
#[derive(Debug, thiserror::Error)]
pub enum ExecutorError {
    /// Recording an evaluation in the simulation log failed.
    #[error(transparent)]
    Log(#[from] LogError),
    /// The thread pool could not be built.
    #[error("thread pool: {0}")]
    Threads(String),
    /// The cluster (Slurm) could not run the simulations.
    #[error("executor: {0}")]
    Executor(String),
}

/// One candidate of a batch.
#[derive(Clone, Copy, Debug)]
pub struct Candidate<'a> {
    /// Its place in the calibration.
    pub key: &'a Key,
    /// Its constants (SI, the model space's order).
    pub values: &'a [f64],
}

/// Candidates of one model, fold and instance, to simulate on the same experiments.
pub struct Batch<'a> {
    /// The campaign.
    pub campaign: &'a Campaign,
    /// The model's space.
    pub space: &'a ModelSpace,
    /// Experiments to simulate (campaign indices).
    pub experiments: &'a [usize],
    /// The optimiser instance's seed.
    pub seed: u64,
    /// The candidates.
    pub candidates: Vec<Candidate<'a>>,
    /// The mesh to simulate them on (each candidate's key carries it too).
    pub fidelity: Fidelity,
}

/// Called once per candidate as its evaluation ends, in any order: `(index in the batch,
/// evaluation, origin)`.
pub type Record<'r> = dyn Fn(usize, &Evaluation, &Origin) -> Result<(), ExecutorError> + Sync + 'r;

/// Predictions of one experiment (the recording's points), or why its simulation failed.
pub type Prediction = Result<Vec<f64>, String>;

/// One prediction job: a realised hypothesis simulated on one campaign experiment.
#[derive(Clone, Copy)]
pub struct PredictionJob<'a> {
    /// The job's journal key (a hash of everything that determines the simulation; it names
    /// the job's Slurm task, so a resumed run finds a result its task wrote).
    pub key: &'a str,
    /// The material and settings to simulate with.
    pub realisation: &'a Realisation,
    /// The experiment (campaign index).
    pub experiment: usize,
}

/// Prediction jobs on one campaign's experiments.
pub struct PredictionBatch<'a> {
    /// The campaign (its experiments; its file, which Slurm workers load).
    pub campaign: &'a Campaign,
    /// The jobs.
    pub jobs: Vec<PredictionJob<'a>>,
}

/// Called once per prediction job as it ends, in any order: `(index in the batch, prediction,
/// origin)`.
pub type RecordPrediction<'r> =
    dyn Fn(usize, &Prediction, &Origin) -> Result<(), ExecutorError> + Sync + 'r;

/// Runs the simulations of batches.
pub trait Executor {
    /// Evaluate every candidate of `batch`, calling `record` as each ends; the evaluations in
    /// the batch's order.
    fn evaluate(
        &mut self,
        batch: &Batch<'_>,
        record: &Record<'_>,
    ) -> Result<Vec<Evaluation>, ExecutorError>;

    /// Simulate every job of `batch`, calling `record` as each ends; the predictions in the
    /// batch's order.
    fn predict(
        &mut self,
        batch: &PredictionBatch<'_>,
        record: &RecordPrediction<'_>,
    ) -> Result<Vec<Prediction>, ExecutorError>;
}

/// This machine's cores: one candidate per thread of a pool, one solver thread each (a batch
/// fills the cores; results do not depend on it).
pub struct Local {
    pool: rayon::ThreadPool,
    settings: SolverSettings,
    origin: Origin,
}

impl Local {
    /// A pool for batches of `parallel` candidates: `parallel` threads, but never more than
    /// this machine's cores (a thread per candidate beyond them only competes for the same
    /// cores; the results do not depend on the pool's size).
    pub fn new(parallel: usize) -> Result<Self, ExecutorError> {
        let cores = std::thread::available_parallelism().map_or(1, usize::from);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(parallel.clamp(1, cores))
            .build()
            .map_err(|e| ExecutorError::Threads(e.to_string()))?;
        Ok(Self {
            pool,
            settings: SolverSettings {
                threads: Some(1),
                ..SolverSettings::default()
            },
            origin: Origin::this_process("local"),
        })
    }

    /// Threads of the pool.
    pub fn threads(&self) -> usize {
        self.pool.current_num_threads()
    }
}

impl Executor for Local {
    fn evaluate(
        &mut self,
        batch: &Batch<'_>,
        record: &Record<'_>,
    ) -> Result<Vec<Evaluation>, ExecutorError> {
        let settings = &self.settings;
        let origin = &self.origin;
        self.pool.install(|| {
            batch
                .candidates
                .par_iter()
                .enumerate()
                .map(|(index, candidate)| {
                    let evaluation = evaluate_at(
                        batch.campaign,
                        batch.space,
                        candidate.values,
                        batch.experiments,
                        settings,
                        batch.fidelity,
                    );
                    record(index, &evaluation, origin)?;
                    Ok(evaluation)
                })
                .collect()
        })
    }

    fn predict(
        &mut self,
        batch: &PredictionBatch<'_>,
        record: &RecordPrediction<'_>,
    ) -> Result<Vec<Prediction>, ExecutorError> {
        let settings = &self.settings;
        let origin = &self.origin;
        let experiments = &batch.campaign.experiments;
        self.pool.install(|| {
            batch
                .jobs
                .par_iter()
                .enumerate()
                .map(|(index, job)| {
                    let prediction = job
                        .realisation
                        .predict(&experiments[job.experiment], settings);
                    record(index, &prediction, origin)?;
                    Ok(prediction)
                })
                .collect()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_local_pool_never_exceeds_the_machines_cores() {
        // GOAL: `parallel = 256` on a small machine does not start 256 threads (issue 52,
        //       item 2): the pool is capped at the cores, the batch size stays the campaign's.
        // SETUP: pools for 1, 2 and 256 candidates at once.
        // REFERENCE: min(parallel, available_parallelism), at least 1.
        let cores = std::thread::available_parallelism().map_or(1, usize::from);
        for parallel in [1, 2, 256] {
            let local = Local::new(parallel).unwrap();
            assert_eq!(local.threads(), parallel.min(cores));
        }
    }
}
