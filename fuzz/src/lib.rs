//! Harness code shared by the cargo-fuzz targets of stoss-kernel (see `fuzz/README.md`).
//!
//! - [`source`]: fuzzer bytes -> bounded numbers, recording whether each lies in its domain;
//! - [`check`]: the properties asserted on every stress update;
//! - [`strength`]: the `strength_update_<model>` targets;
//! - [`eos`]: the `eos` target;
//! - [`rht`]: the `rht_update` target (RHT concrete);
//! - [`kc`]: the `kc_update` target (K&C concrete);
//! - [`lanes`]: the `update_lanes` target (the group update against the one-point update).
//!
//! Every target is a function of the input bytes only (no clock, no randomness, no I/O), so a
//! crash reproduces from its artifact file.

// `!(x >= 0.0)` is deliberate throughout: it is also true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod check;
pub mod eos;
pub mod kc;
pub mod lanes;
pub mod rht;
pub mod source;
pub mod strength;
