//! Closed-form and ODE models that cross-check the FE experiments.

pub mod ballistic;
pub mod concrete;
pub mod penetration;
pub mod riemann;
