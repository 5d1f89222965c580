//! The `stoss` binary.

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    stoss::cli::run(stoss::cli::Cli::parse())
}
