//! A request to stop a calibration or diagnosis cleanly (SIGINT, or SIGTERM as Slurm sends it
//! before it kills a job): the run finishes the batch of simulations in flight, logs each
//! result as usual, and stops with [`Interrupted`] instead of starting another batch, so that
//! `--resume` continues from the log without running anything twice.
//!
//! The flag is process-wide; the command line installs the signal handler
//! ([`install_handler`]); the library only reads the flag between batches.

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// A run stopped on request: every finished simulation is in its log.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("interrupted: the simulations in flight finished and are logged")]
pub struct Interrupted;

/// Whether a stop was requested.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}

/// Request a stop (what the signal handler does; tests call it directly).
pub fn request() {
    REQUESTED.store(true, Ordering::SeqCst);
}

/// `Err(Interrupted)` if a stop was requested.
pub fn check() -> Result<(), Interrupted> {
    if requested() {
        Err(Interrupted)
    } else {
        Ok(())
    }
}

/// Install the handler of SIGINT and SIGTERM: the first signal requests a stop after the
/// simulations in flight (and says so on stderr); a second one ends the process at once
/// (exit 130: the simulations still running are lost, the logged ones are kept).
pub fn install_handler() -> Result<(), String> {
    ctrlc::set_handler(|| {
        if requested() {
            eprintln!("\nstopped at once; the finished simulations are in the log");
            std::process::exit(130);
        }
        request();
        eprintln!(
            "\nstopping: the simulations in flight finish and are logged first (interrupt \
             again to stop at once)"
        );
    })
    .map_err(|e| format!("signal handler: {e}"))
}
