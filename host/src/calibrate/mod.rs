//! `stoss calibrate`: fit model constants to recordings of functional experiments by Bayesian
//! optimisation over simulations (seed 000 sec. 4): campaign files, the error measure, the
//! simulation log that makes runs resumable, the protocols (instances, leave-one-out, model
//! selection), the linearised uncertainty of the calibrated constants and the report.

pub mod campaign;
pub mod direct_jc;
pub mod executor;
pub mod log;
pub mod objective;
pub mod polish;
pub mod proposer;
pub mod run;
pub mod uncertainty;

pub use crate::fit::ModelSpace;
pub use campaign::Campaign;
pub use objective::{evaluate, score, Evaluation, Score, Status};
