//! Closed-form and ODE models that cross-check the FE experiments.

pub mod ballistic;
pub mod penetration;
pub mod riemann;
