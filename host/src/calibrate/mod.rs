//! `stoss calibrate`: fit model constants to recordings of functional experiments by Bayesian
//! optimisation over simulations (seed 000 sec. 4): the protocols (instances, leave-one-out,
//! model selection), the proposers, the Nelder-Mead polish and the direct JC fit of flow
//! curves. The campaign, the error measure, the executors, the simulation log, the results and
//! their uncertainty are the fitting layer's ([`crate::fit`]), shared with `stoss diagnose`.

pub mod cost;
pub mod direct_jc;
pub mod polish;
pub mod proposer;
pub mod run;
