//! The command line's executor flags, shared by `stoss calibrate` and `stoss diagnose`: where
//! the simulations run (this machine, a Slurm cluster) and how, over the campaign's
//! `[executor]` table.

use crate::fit::executor::slurm::SlurmExecutor;
use crate::fit::executor::{Executor, ExecutorEntry, ExecutorKind, Local, SlurmMode};
use crate::fit::Campaign;
use clap::Args;
use std::path::Path;

/// Executor flags (each overrides the campaign's `[executor]` field of the same name).
#[derive(Debug, Args)]
pub struct ExecutorArgs {
    /// Where the simulations run: `local` (this machine) or `slurm` (tasks of a Slurm
    /// cluster); overrides the campaign's `[executor] kind`.
    #[arg(long = "executor", value_enum)]
    pub kind: Option<ExecutorKind>,
    /// Slurm placement: `array` (a job array per batch) or `allocation` (one allocation,
    /// an `srun` step per simulation task).
    #[arg(long, value_enum)]
    pub slurm_mode: Option<SlurmMode>,
    /// Slurm partition.
    #[arg(long)]
    pub partition: Option<String>,
    /// Slurm time limit of one task's simulations (`MM:SS`, `HH:MM:SS`, `D-HH:MM:SS`...).
    #[arg(long)]
    pub time_limit: Option<String>,
    /// CPUs (solver threads) per Slurm task.
    #[arg(long)]
    pub cpus_per_task: Option<usize>,
    /// Slurm tasks running at once.
    #[arg(long)]
    pub max_concurrent: Option<usize>,
    /// An extra argument of sbatch (array) or salloc (allocation); repeat for several.
    #[arg(long = "sbatch-arg", value_name = "ARG", allow_hyphen_values = true)]
    pub sbatch_args: Vec<String>,
}

impl ExecutorArgs {
    /// The campaign's `[executor]` table with these overrides, checked; errors name the flag.
    pub fn settings(&self, campaign: &ExecutorEntry) -> Result<ExecutorEntry, String> {
        let mut entry = campaign.clone();
        if let Some(kind) = self.kind {
            entry.kind = kind;
        }
        if let Some(mode) = self.slurm_mode {
            entry.mode = mode;
        }
        if let Some(partition) = &self.partition {
            entry.partition = Some(partition.clone());
        }
        if let Some(limit) = &self.time_limit {
            entry.time_limit = Some(limit.clone());
        }
        if let Some(cpus) = self.cpus_per_task {
            entry.cpus_per_task = cpus;
        }
        if let Some(n) = self.max_concurrent {
            entry.max_concurrent = Some(n);
        }
        entry.sbatch_args.extend(self.sbatch_args.iter().cloned());
        entry.check().map_err(|(field, message)| {
            format!(
                "--{} (or [executor] {field}): {message}",
                field.replace('_', "-")
            )
        })?;
        Ok(entry)
    }
}

/// The executor `entry` names: this machine's pool of `parallel` threads, or the Slurm
/// executor working in `output/slurm` (`parallel` tasks at once unless the entry says).
pub fn start_executor(
    entry: &ExecutorEntry,
    parallel: usize,
    campaign: &Campaign,
    output: &Path,
    quiet: bool,
) -> Result<Box<dyn Executor>, String> {
    Ok(match entry.kind {
        ExecutorKind::Local => {
            // Options that would be silently ignored: said once (issue 52, item 5).
            let ignored = entry.slurm_only_fields_set();
            if !ignored.is_empty() {
                eprintln!(
                    "warning: [executor] {} only apply to the slurm executor; this run is \
                     local, so they are ignored",
                    ignored.join(", ")
                );
            }
            Box::new(Local::new(parallel).map_err(|e| e.to_string())?)
        }
        ExecutorKind::Slurm => Box::new(
            SlurmExecutor::start(
                entry,
                entry.max_concurrent.unwrap_or(parallel),
                campaign,
                output,
                quiet,
            )
            .map_err(|e| e.to_string())?,
        ),
    })
}
