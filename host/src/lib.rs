//! # stoss
//!
//! Host side of stoss: verification of the kernel, and (as the project grows) meshes, the
//! explicit solver, the functional experiments, calibration and diagnosis.

pub mod analytic;
pub mod blast;
pub mod calibrate;
pub mod cli;
pub mod diagnose;
pub mod euler;
pub mod experiment;
pub mod figure;
pub mod fit;
pub mod hash;
pub mod history;
pub mod input;
pub mod journal;
pub mod measure;
pub mod mesh;
pub mod optimise;
pub mod random;
pub mod report;
pub mod run_lock;
pub mod solver;
pub mod validate;
pub mod verify;
