//! `stoss verify`: the kernel against closed forms and published numbers, and the golden
//! bit-exact histories.

pub mod checks;
pub mod golden;
pub mod history;
pub mod materials;

pub use checks::{run_all, CheckResult, Expectation};
pub use history::History;
