//! Simulations of constant sets outside the executor, run as one pool: what a calibration
//! simulates after its search (the linearisation's forward differences, the report's
//! overlays of every model's selected and starting constants).
//!
//! Each job is one constant set on one campaign experiment, run with one solver thread; the
//! jobs are spread over the process's thread pool (one job per core at a time), so a long
//! simulation and many short ones pack without a serial tail, and the results come back in
//! job order. A simulation's results do not depend on its thread count (the solvers are
//! deterministic for any), so a job's outcome is the one `stoss simulate` gives.

use super::campaign::Campaign;
use super::ModelSpace;
use crate::experiment::Outcome;
use crate::solver::SolverSettings;
use rayon::prelude::*;

/// One simulation: the constants `values` of `space` (with the set-up values they hold) on
/// campaign experiment `experiment`.
#[derive(Clone, Copy, Debug)]
pub struct Job<'a> {
    /// The model's search space, which writes the constants into a material.
    pub space: &'a ModelSpace,
    /// The constants (and set-up values) in the space's order.
    pub values: &'a [f64],
    /// The campaign experiment's index.
    pub experiment: usize,
}

/// Simulate `job` with `settings`: the material and set-up its values give; errors name the
/// experiment file.
pub fn simulate(
    campaign: &Campaign,
    job: &Job<'_>,
    settings: &SolverSettings,
) -> Result<Outcome, String> {
    let (_, material) = job.space.material(&campaign.base, job.values)?;
    let setup = job.space.setup_values(job.values);
    let experiment = super::space::with_setup(&campaign.experiments[job.experiment], &setup)?;
    experiment
        .simulate(&material, settings)
        .map_err(|error| format!("{}: {error}", experiment.file.name))
}

/// Every job simulated, one solver thread each, the jobs spread over the thread pool; `keep`
/// turns job `k`'s outcome into what the caller holds on to (all of it, or only its
/// predictions), so the pool never holds more than it needs. Results in job order.
pub fn simulate_all<T: Send>(
    campaign: &Campaign,
    jobs: &[Job<'_>],
    keep: impl Fn(usize, Outcome) -> T + Sync,
) -> Vec<Result<T, String>> {
    let settings = SolverSettings {
        threads: Some(1),
        ..SolverSettings::default()
    };
    jobs.par_iter()
        .enumerate()
        .map(|(k, job)| simulate(campaign, job, &settings).map(|outcome| keep(k, outcome)))
        .collect()
}
