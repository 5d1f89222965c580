//! `stoss evaluate <task file>`: the worker of a distributed calibration. It simulates one
//! candidate that a `stoss calibrate` coordinator wrote as a task file and writes the result
//! file beside it atomically (fit/executor/task.rs). `--probe FILE` only writes this
//! worker's origin (version, binary hash, host), which the coordinator checks before it
//! submits any simulation.

use super::output::say;
use crate::fit::executor::task::{run_task, write_probe};
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `stoss evaluate`.
#[derive(Debug, Args)]
pub struct EvaluateArgs {
    /// Task file (`<run folder>/slurm/tasks/*.task.json`).
    #[arg(required_unless_present = "probe")]
    pub task: Option<PathBuf>,
    /// Solver threads (results do not depend on it).
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
    /// Write this worker's stoss version, binary hash and host name to FILE, and exit.
    #[arg(long, value_name = "FILE", conflicts_with = "task")]
    pub probe: Option<PathBuf>,
}

/// Run `stoss evaluate`.
pub fn run(args: &EvaluateArgs) -> ExitCode {
    let outcome = match (&args.probe, &args.task) {
        (Some(probe), _) => write_probe(probe).map(|()| probe.clone()),
        (None, Some(task)) => {
            let most = crate::solver::explicit::MAXIMUM_THREADS;
            if !(1..=most).contains(&args.threads) {
                Err(format!("--threads {}: give 1 to {most}", args.threads))
            } else {
                run_task(task, args.threads)
            }
        }
        (None, None) => Err("give a task file or --probe FILE".into()),
    };
    match outcome {
        Ok(path) => {
            say!("{}", path.display());
            super::output::json(&serde_json::json!({"command": "evaluate", "result": path}));
            ExitCode::SUCCESS
        }
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}
