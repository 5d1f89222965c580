//! The `[executor]` table of a campaign and the `--executor` flags of `stoss calibrate`: where
//! the simulations of a batch run (this machine, or tasks of a Slurm cluster) and how.

use serde::{Deserialize, Serialize};

/// Where the candidates of a batch are simulated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum ExecutorKind {
    /// This machine's cores (a thread per candidate).
    #[default]
    Local,
    /// Tasks of a Slurm cluster, each running `stoss evaluate` on one candidate.
    Slurm,
}

/// How the Slurm executor places its tasks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum SlurmMode {
    /// One job array per batch (`sbatch --array`): each batch queues again.
    #[default]
    Array,
    /// One allocation held for the whole calibration (`salloc --no-shell`), each candidate an
    /// `srun` step inside it: no queue wait between batches.
    Allocation,
}

fn default_cpus_per_task() -> usize {
    1
}
fn default_retries() -> usize {
    2
}
fn default_poll_interval() -> f64 {
    1.0
}
fn default_result_wait() -> f64 {
    10.0
}
fn default_probe_timeout() -> f64 {
    600.0
}

/// The `[executor]` table of a campaign.
///
/// ```toml
/// [executor]
/// kind = "slurm"              # "local" (default) or "slurm"
/// mode = "array"              # "array" (a job array per batch) or "allocation"
/// partition = "compute"
/// time_limit = "00:20:00"     # per candidate (all its simulations), Slurm's time format
/// cpus_per_task = 2           # solver threads of each candidate
/// max_concurrent = 8          # tasks running at once (default: the optimiser's parallel)
/// sbatch_args = ["--account=impact", "--qos=normal"]
/// prologue = ["module load gcc/12"]   # shell lines each task runs before stoss
/// retries = 2                 # a failed, cancelled, timed-out or node-lost task is rerun
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExecutorEntry {
    /// Local or Slurm.
    #[serde(default)]
    pub kind: ExecutorKind,
    /// Job array per batch, or one allocation with `srun` steps.
    #[serde(default)]
    pub mode: SlurmMode,
    /// Slurm partition (default: the cluster's default partition).
    #[serde(default)]
    pub partition: Option<String>,
    /// Time limit of one candidate's simulations, in Slurm's format (`minutes`, `MM:SS`,
    /// `HH:MM:SS`, `D-HH`, `D-HH:MM`, `D-HH:MM:SS`).
    #[serde(default)]
    pub time_limit: Option<String>,
    /// Time limit of the allocation in `allocation` mode (default: the partition's limit).
    #[serde(default)]
    pub allocation_time_limit: Option<String>,
    /// CPUs per task; the candidate's solver runs that many threads (results do not depend on
    /// it).
    #[serde(default = "default_cpus_per_task")]
    pub cpus_per_task: usize,
    /// Tasks running at once (default: the optimiser's `parallel`, the batch size).
    #[serde(default)]
    pub max_concurrent: Option<usize>,
    /// Extra arguments of `sbatch` (array mode) or `salloc` (allocation mode).
    #[serde(default)]
    pub sbatch_args: Vec<String>,
    /// Shell lines each task runs before stoss (a module environment, say).
    #[serde(default)]
    pub prologue: Vec<String>,
    /// Reruns of a task that ends without a result before its candidate is recorded as failed.
    #[serde(default = "default_retries")]
    pub retries: usize,
    /// Seconds between two looks at the queue and the run folder.
    #[serde(default = "default_poll_interval")]
    pub poll_interval: f64,
    /// Seconds a task's result may take to appear in the run folder after the task ended (the
    /// attribute cache of a shared filesystem).
    #[serde(default = "default_result_wait")]
    pub result_wait: f64,
    /// Seconds the probe task (which checks that workers run this stoss and see the run
    /// folder) may wait in the queue and run.
    #[serde(default = "default_probe_timeout")]
    pub probe_timeout: f64,
}

impl Default for ExecutorEntry {
    fn default() -> Self {
        Self {
            kind: ExecutorKind::Local,
            mode: SlurmMode::Array,
            partition: None,
            time_limit: None,
            allocation_time_limit: None,
            cpus_per_task: default_cpus_per_task(),
            max_concurrent: None,
            sbatch_args: Vec::new(),
            prologue: Vec::new(),
            retries: default_retries(),
            poll_interval: default_poll_interval(),
            result_wait: default_result_wait(),
            probe_timeout: default_probe_timeout(),
        }
    }
}

/// Most tasks of a job array stoss submits at once, and most CPUs per task.
pub const MAXIMUM_TASKS: usize = 10_000;

impl ExecutorEntry {
    /// The fields set here that only the Slurm executor reads (a local run ignores them).
    pub fn slurm_only_fields_set(&self) -> Vec<&'static str> {
        [
            ("partition", self.partition.is_some()),
            ("time_limit", self.time_limit.is_some()),
            (
                "allocation_time_limit",
                self.allocation_time_limit.is_some(),
            ),
            ("max_concurrent", self.max_concurrent.is_some()),
            ("sbatch_args", !self.sbatch_args.is_empty()),
            ("prologue", !self.prologue.is_empty()),
        ]
        .into_iter()
        .filter_map(|(name, set)| set.then_some(name))
        .collect()
    }

    /// Check the settings; `Err((field, message))` names the first bad one.
    pub fn check(&self) -> Result<(), (&'static str, String)> {
        for (field, limit) in [
            ("time_limit", &self.time_limit),
            ("allocation_time_limit", &self.allocation_time_limit),
        ] {
            if let Some(limit) = limit {
                slurm_time_seconds(limit).map_err(|message| (field, message))?;
            }
        }
        if self.cpus_per_task == 0 || self.cpus_per_task > crate::solver::explicit::MAXIMUM_THREADS
        {
            return Err((
                "cpus_per_task",
                format!(
                    "{} CPUs per task: give 1 to {}",
                    self.cpus_per_task,
                    crate::solver::explicit::MAXIMUM_THREADS
                ),
            ));
        }
        if let Some(n) = self.max_concurrent {
            if n == 0 || n > MAXIMUM_TASKS {
                return Err((
                    "max_concurrent",
                    format!("{n} tasks at once: give 1 to {MAXIMUM_TASKS}"),
                ));
            }
        }
        if self.retries > 100 {
            return Err((
                "retries",
                format!("{} reruns per task: give at most 100", self.retries),
            ));
        }
        for (field, seconds, least) in [
            ("poll_interval", self.poll_interval, 0.05),
            ("result_wait", self.result_wait, 0.0),
            ("probe_timeout", self.probe_timeout, 1.0),
        ] {
            if !(seconds.is_finite() && seconds >= least && seconds <= 86_400.0) {
                return Err((
                    field,
                    format!("{seconds} s: give a number of seconds from {least} to 86400"),
                ));
            }
        }
        if let Some(partition) = &self.partition {
            if partition.is_empty() || partition.contains(char::is_whitespace) {
                return Err((
                    "partition",
                    format!("{partition:?} is not a partition name"),
                ));
            }
        }
        Ok(())
    }
}

/// Seconds of a Slurm time limit: `minutes`, `MM:SS`, `HH:MM:SS`, `D-HH`, `D-HH:MM` or
/// `D-HH:MM:SS` (sbatch(1), `--time`); `UNLIMITED`/`INFINITE` are refused (a task that never
/// ends would stall the calibration).
pub fn slurm_time_seconds(text: &str) -> Result<u64, String> {
    let bad = || {
        format!(
            "{text:?} is not a Slurm time limit: give minutes, MM:SS, HH:MM:SS, D-HH, D-HH:MM or \
             D-HH:MM:SS, at least one minute"
        )
    };
    let number = |part: &str| -> Result<u64, String> {
        if part.is_empty() || part.len() > 6 || !part.bytes().all(|b| b.is_ascii_digit()) {
            return Err(bad());
        }
        part.parse().map_err(|_| bad())
    };
    let (days, rest) = match text.split_once('-') {
        Some((days, rest)) => (Some(number(days)?), rest),
        None => (None, text),
    };
    let parts: Vec<u64> = rest.split(':').map(number).collect::<Result<_, _>>()?;
    let seconds = match (days, parts.as_slice()) {
        (None, [m]) => m * 60,
        (None, [m, s]) => m * 60 + s,
        (None, [h, m, s]) => h * 3600 + m * 60 + s,
        (Some(d), [h]) => d * 86_400 + h * 3600,
        (Some(d), [h, m]) => d * 86_400 + h * 3600 + m * 60,
        (Some(d), [h, m, s]) => d * 86_400 + h * 3600 + m * 60 + s,
        _ => return Err(bad()),
    };
    // Slurm counts limits in whole minutes (a limit under a minute is one minute).
    if seconds < 60 {
        return Err(bad());
    }
    Ok(seconds)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slurm_time_formats_parse_to_seconds() {
        // GOAL: every time format of sbatch --time is understood; nonsense is refused.
        // SETUP: the six forms, and bad strings.
        // REFERENCE: sbatch(1), option --time.
        assert_eq!(slurm_time_seconds("30"), Ok(1800));
        assert_eq!(slurm_time_seconds("5:30"), Ok(330));
        assert_eq!(slurm_time_seconds("01:02:03"), Ok(3723));
        assert_eq!(slurm_time_seconds("2-03"), Ok(2 * 86_400 + 3 * 3600));
        assert_eq!(slurm_time_seconds("1-00:10"), Ok(86_400 + 600));
        assert_eq!(slurm_time_seconds("1-00:00:30"), Ok(86_430));
        for bad in [
            "",
            "ten",
            "1:2:3:4",
            "-5",
            "1-",
            "0",
            "0:30",
            "UNLIMITED",
            "1.5",
            "9999999",
        ] {
            assert!(slurm_time_seconds(bad).is_err(), "{bad:?} accepted");
        }
    }

    #[test]
    fn executor_settings_are_checked() {
        // GOAL: bad executor settings name their field. SETUP: one bad field at a time.
        // REFERENCE: the limits stated in `check`.
        assert!(ExecutorEntry::default().check().is_ok());
        let field = |entry: ExecutorEntry| entry.check().unwrap_err().0;
        let base = ExecutorEntry::default;
        assert_eq!(
            field(ExecutorEntry {
                time_limit: Some("soon".into()),
                ..base()
            }),
            "time_limit"
        );
        assert_eq!(
            field(ExecutorEntry {
                cpus_per_task: 0,
                ..base()
            }),
            "cpus_per_task"
        );
        assert_eq!(
            field(ExecutorEntry {
                max_concurrent: Some(0),
                ..base()
            }),
            "max_concurrent"
        );
        assert_eq!(
            field(ExecutorEntry {
                poll_interval: f64::NAN,
                ..base()
            }),
            "poll_interval"
        );
        assert_eq!(
            field(ExecutorEntry {
                partition: Some("two words".into()),
                ..base()
            }),
            "partition"
        );
    }
}
