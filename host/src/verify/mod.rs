//! `stoss verify`: the kernel against closed forms and published numbers, and the golden
//! bit-exact histories. [`checks::run_all`] is the one list of rows: the metal checks of
//! [`checks`], then the equations of state ([`eos_checks`]), RHT concrete ([`rht_checks`])
//! and K&C concrete ([`kc_checks`]).

pub mod checks;
pub mod eos_checks;
pub mod golden;
pub mod kc_checks;
pub mod materials;
pub mod rht_checks;

pub use checks::{run_all, CheckResult, Expectation};
