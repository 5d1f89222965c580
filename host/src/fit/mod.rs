//! The fitting layer under `calibrate` and `diagnose`: what both need to turn named, bounded
//! constants into simulations and fit them, and nothing of either.
//!
//! - [`space`]: a model's search space (names, search bounds, the strength they are written
//!   into) and the at-a-bound check;
//! - [`unit_cube`]: the one map between bounds and unit coordinates;
//! - [`hypothesis`]: a material with experiment-level settings and fitted constants, and its
//!   realisation (the kernel material the simulations run);
//! - [`engine`]: batches of simulations in parallel, journalled and replayed on a rerun;
//! - [`least_squares`]: the bounded Levenberg-Marquardt fit on whitened residuals;
//! - [`linear`]: the small dense least-squares algebra it needs;
//! - [`campaign`]: the campaign file (models, experiments, optimiser, executor settings);
//! - [`objective`]: the error measure of a candidate over a campaign's recordings;
//! - [`fidelity`]: multi-fidelity: the coarse meshes' predictions corrected towards the fine;
//! - [`executor`]: where candidates are simulated (this machine's pool, a Slurm cluster);
//! - [`log`]: the simulation log that makes a calibration resumable;
//! - [`result`]: what a calibration returns per model (`result.json`), read back by the
//!   diagnosis and the report;
//! - [`uncertainty`]: the linearised uncertainty of fitted constants;
//! - [`posterior`]: their sampled posterior and the prediction bands it gives;
//! - [`outcomes`]: the simulations after a search (forward differences, the report's
//!   overlays), pooled outside the executor.
//!
//! It may import the experiment layer and everything below it (experiment, solver, input,
//! journal, hash, the kernel); it imports neither `calibrate` nor `diagnose`
//! (`docs/architecture.md`).

pub mod campaign;
pub mod engine;
pub mod executor;
pub mod fidelity;
pub mod hypothesis;
pub mod interrupt;
pub mod least_squares;
pub mod linear;
pub mod log;
pub mod objective;
pub mod outcomes;
pub mod posterior;
pub mod result;
pub mod space;
pub mod uncertainty;
pub mod unit_cube;

pub use campaign::Campaign;
pub use objective::{
    describe_scales, error_scales, evaluate, evaluate_at, score, Evaluation, QuantityScale,
    ScaleKind, Score, Status,
};

pub use engine::{Engine, Progress};
pub use hypothesis::{Hypothesis, Parameter};
pub use least_squares::{levenberg_marquardt, Fit};
pub use space::ModelSpace;

/// Why a fit (or a batch of its simulations) stopped. The messages are those the diagnosis
/// has always reported (the diagnosis' error converts variant for variant).
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// Reading or writing the journal failed.
    #[error("{0}")]
    Io(String),
    /// The executor (this machine's pool, Slurm) could not run the simulations.
    #[error(transparent)]
    Executor(#[from] executor::ExecutorError),
    /// A simulation the fit cannot do without failed.
    #[error("simulation failed: {0}")]
    Simulation(String),
    /// Stopped on request after the batch in flight was journalled ([`interrupt`]).
    #[error(transparent)]
    Interrupted(#[from] interrupt::Interrupted),
}
