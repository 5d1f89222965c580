//! How the command line speaks, the same on every subcommand: results on stdout, progress and
//! logs on stderr. Three global flags, set once when the command line is parsed:
//!
//! - `--quiet`: no progress and no log lines (errors and warnings still reach stderr);
//! - `--verbose`: progress at every event instead of at most every few seconds;
//! - `--json`: the result as one JSON document on stdout (`{"command": ..., ...}`), in place
//!   of the text tables; progress and logs stay on stderr.

use std::sync::OnceLock;

/// The global output flags.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Output {
    /// `--quiet`.
    pub quiet: bool,
    /// `--verbose`.
    pub verbose: bool,
    /// `--json`.
    pub json: bool,
}

static OUTPUT: OnceLock<Output> = OnceLock::new();

/// Record the flags (the first call wins; the binary makes one).
pub fn set(output: Output) {
    let _ = OUTPUT.set(output);
}

/// The flags of this run (all off if none were recorded: the library called directly).
pub fn get() -> Output {
    OUTPUT.get().copied().unwrap_or_default()
}

/// Whether progress and log lines are printed (not `--quiet`).
pub fn logging() -> bool {
    !get().quiet
}

/// Print the result document `value` on stdout if `--json` was given.
pub fn json(value: &serde_json::Value) {
    if get().json {
        println!(
            "{}",
            serde_json::to_string_pretty(value).unwrap_or_else(|_| "null".into())
        );
    }
}

/// A result line on stdout, left out under `--json` (the JSON document carries the result).
macro_rules! say {
    () => {
        if !$crate::cli::output::get().json {
            println!();
        }
    };
    ($($arg:tt)*) => {
        if !$crate::cli::output::get().json {
            println!($($arg)*);
        }
    };
}

/// Result text on stdout without a line end, left out under `--json`.
macro_rules! say_inline {
    ($($arg:tt)*) => {
        if !$crate::cli::output::get().json {
            print!($($arg)*);
        }
    };
}

/// A progress or log line on stderr, left out under `--quiet`.
macro_rules! log_line {
    ($($arg:tt)*) => {
        if $crate::cli::output::logging() {
            eprintln!($($arg)*);
        }
    };
}

pub(crate) use {log_line, say, say_inline};
