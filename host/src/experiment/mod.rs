//! Functional experiments: geometry, loading, and the measurement extracted exactly as the
//! experiment records it.

pub mod taylor;
