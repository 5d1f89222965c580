//! stoss host crate.
