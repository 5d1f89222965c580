//! The Slurm executor: each item of a batch (a calibration candidate, or a prediction job of
//! a least-squares fit) is a Slurm task running `stoss evaluate <task file>` (`task.rs`),
//! which writes its result file atomically into the run folder on the shared filesystem; the
//! coordinator (`stoss calibrate`, `stoss diagnose`) polls the folder and the queue, logs each
//! result as it arrives, reruns tasks that end without one, and returns the batch in order.
//! Both kinds of batch go through one machinery ([`Work`]).
//!
//! Two placements (`[executor] mode`):
//! - `array`: one job array per batch (`sbatch --parsable --array=0-(n-1)%max`). Each batch
//!   queues again; nothing is held between batches.
//! - `allocation`: one allocation for the whole calibration (`salloc --no-shell`), each
//!   candidate an `srun --exact` step inside it: no queue wait per batch.
//!
//! Before the first batch a probe task runs `stoss evaluate --probe`: it proves that the
//! workers run this very binary (same SHA-256) and that a file they write into the run folder
//! is seen here. A resumed calibration adopts the results that tasks of the killed run wrote
//! after the coordinator died (same key, bit-identical constants, same binary) instead of
//! running them again.

use super::super::campaign::Campaign;
use super::super::objective::{Evaluation, Status};
use super::settings::{ExecutorEntry, SlurmMode};
use super::task::{
    binary_sha256, prediction_task_name, result_path, sha256_hex, task_name, write_atomically,
    Origin, PredictionResultFile, PredictionTaskFile, RealisationRecord, ResultFile, TaskFile,
};
use super::{
    Batch, Executor, ExecutorError, Prediction, PredictionBatch, Record, RecordPrediction,
};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Task states after which a task will not write its result any more (squeue(1), JOB STATE
/// CODES). Any other state counts as still queued or running.
const ENDED_STATES: [&str; 10] = [
    "COMPLETED",
    "FAILED",
    "CANCELLED",
    "TIMEOUT",
    "NODE_FAIL",
    "OUT_OF_MEMORY",
    "PREEMPTED",
    "BOOT_FAIL",
    "DEADLINE",
    "SPECIAL_EXIT",
];

/// This run's tasks in the queue: `(job id, array index) -> (state, reason)`.
type QueueStates = BTreeMap<(String, usize), (String, String)>;

/// How long the queue may stay unreadable (squeue failing) before the calibration stops.
const QUEUE_UNREADABLE_LIMIT: Duration = Duration::from_secs(300);

/// Least time between two readings of the queue (squeue): results are found in the run folder
/// at every poll; the queue only tells which tasks ended without one, and a scheduler should
/// not be polled every second.
const QUEUE_READ_INTERVAL: Duration = Duration::from_secs(10);

/// Least time between two lines about tasks waiting in the queue.
const WAITING_REPORT_INTERVAL: Duration = Duration::from_secs(60);

fn executor_error(message: impl Into<String>) -> ExecutorError {
    ExecutorError::Executor(message.into())
}

/// `text` quoted for a POSIX shell.
fn shell_quote(text: &str) -> String {
    format!("'{}'", text.replace('\'', r"'\''"))
}

/// The path of `program` on `PATH`, if it is there.
fn on_path(program: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|folder| folder.join(program))
        .find(|candidate| candidate.is_file())
}

/// Run a Slurm client command; its stdout, or a message quoting its stderr.
fn run_command(program: &str, args: &[String]) -> Result<String, String> {
    let output = Command::new(program)
        .args(args)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("{program}: {e}"))?;
    if output.status.success() {
        Ok(String::from_utf8_lossy(&output.stdout).into_owned())
    } else {
        Err(format!(
            "`{program} {}` failed ({}): {}",
            args.join(" "),
            output.status,
            String::from_utf8_lossy(&output.stderr).trim()
        ))
    }
}

/// The last `lines` non-empty lines of a task's output file, joined by " | ".
fn tail_of(path: &Path, lines: usize) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let kept: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
    kept[kept.len().saturating_sub(lines)..].join(" | ")
}

/// A batch of work as the Slurm executor runs it: one task file per item, one result file
/// back, each result recorded as it arrives.
trait Work {
    /// What one item gives.
    type Output: Clone;
    /// Items in the batch.
    fn len(&self) -> usize;
    /// The item's task file name (without `.task.json`), stable across runs so that a
    /// resumed run finds a result its task wrote.
    fn task_name(&self, index: usize) -> String;
    /// The item's task file (JSON).
    fn task_json(&self, index: usize, executor: &SlurmExecutor) -> Result<Vec<u8>, String>;
    /// The item's output from a result file's text, if the file answers this very item and
    /// was written by this binary.
    fn read_result(&self, index: usize, text: &str) -> Option<(Self::Output, Origin)>;
    /// The output of an item whose task ended without a result on every run allowed.
    fn failed(&self, index: usize, reason: String) -> Self::Output;
    /// Record an item's output as it arrives (the coordinator's log).
    fn record(
        &self,
        index: usize,
        output: &Self::Output,
        origin: &Origin,
    ) -> Result<(), ExecutorError>;
}

/// The candidates of an optimiser batch.
struct Candidates<'b, 'a> {
    batch: &'b Batch<'a>,
    record: &'b Record<'b>,
}

impl Work for Candidates<'_, '_> {
    type Output = Evaluation;

    fn len(&self) -> usize {
        self.batch.candidates.len()
    }

    fn task_name(&self, index: usize) -> String {
        task_name(self.batch.candidates[index].key)
    }

    fn task_json(&self, index: usize, executor: &SlurmExecutor) -> Result<Vec<u8>, String> {
        let candidate = self.batch.candidates[index];
        let file = TaskFile {
            campaign: executor.campaign.clone(),
            campaign_sha256: executor.campaign_sha256.clone(),
            model: self.batch.space.name.clone(),
            key: candidate.key.clone(),
            seed: self.batch.seed,
            experiments: self.batch.experiments.to_vec(),
            constants: TaskFile::named(self.batch.space, candidate.values),
            values: Vec::new(),
            executor: executor.executor_name().into(),
        };
        serde_json::to_vec_pretty(&file).map_err(|e| e.to_string())
    }

    fn read_result(&self, index: usize, text: &str) -> Option<(Evaluation, Origin)> {
        let candidate = self.batch.candidates[index];
        let result: ResultFile = serde_json::from_str(text).ok()?;
        let values = &result.evaluation.values;
        let same_values = values.len() == candidate.values.len()
            && values
                .iter()
                .zip(candidate.values)
                .all(|(a, b)| a.to_bits() == b.to_bits());
        (result.key == *candidate.key
            && same_values
            && result.origin.binary_sha256 == binary_sha256())
        .then_some((result.evaluation, result.origin))
    }

    fn failed(&self, index: usize, reason: String) -> Evaluation {
        Evaluation::labelled(
            self.batch.campaign,
            self.batch.space,
            self.batch.candidates[index].values,
            vec![None; self.batch.campaign.experiments.len()],
            Status::Failed(reason),
            0.0,
        )
    }

    fn record(
        &self,
        index: usize,
        output: &Evaluation,
        origin: &Origin,
    ) -> Result<(), ExecutorError> {
        (self.record)(index, output, origin)
    }
}

/// The prediction jobs of a least-squares fit.
struct Predictions<'b, 'a> {
    batch: &'b PredictionBatch<'a>,
    record: &'b RecordPrediction<'b>,
}

impl Work for Predictions<'_, '_> {
    type Output = Prediction;

    fn len(&self) -> usize {
        self.batch.jobs.len()
    }

    fn task_name(&self, index: usize) -> String {
        prediction_task_name(self.batch.jobs[index].key)
    }

    fn task_json(&self, index: usize, executor: &SlurmExecutor) -> Result<Vec<u8>, String> {
        let job = self.batch.jobs[index];
        let file = PredictionTaskFile {
            campaign: executor.campaign.clone(),
            campaign_sha256: executor.campaign_sha256.clone(),
            key: job.key.into(),
            experiment: job.experiment,
            realisation: RealisationRecord::of(job.realisation),
            executor: executor.executor_name().into(),
        };
        serde_json::to_vec_pretty(&file).map_err(|e| e.to_string())
    }

    fn read_result(&self, index: usize, text: &str) -> Option<(Prediction, Origin)> {
        let result: PredictionResultFile = serde_json::from_str(text).ok()?;
        (result.key == self.batch.jobs[index].key && result.origin.binary_sha256 == binary_sha256())
            .then(|| (result.prediction(), result.origin))
    }

    fn failed(&self, _: usize, reason: String) -> Prediction {
        Err(reason)
    }

    fn record(
        &self,
        index: usize,
        output: &Prediction,
        origin: &Origin,
    ) -> Result<(), ExecutorError> {
        (self.record)(index, output, origin)
    }
}

/// Why one run of a task ended without a result.
#[derive(Clone, Debug, PartialEq)]
pub struct TaskFailure {
    /// Slurm's state (`CANCELLED`, `TIMEOUT`, ...) or the step's exit status.
    pub state: String,
    /// What else is known (reason, the end of the task's output).
    pub detail: String,
    /// The task ran past its time limit.
    pub timed_out: bool,
}

/// What to do with a candidate whose task ended without a result, after its failures so far.
#[derive(Debug, PartialEq)]
pub enum AfterFailure {
    /// Run it again.
    Retry,
    /// Record the candidate as failed, with this reason.
    RecordFailed(String),
    /// Stop the calibration: every run hit the time limit, so the limit is too short.
    TimeLimitTooShort(String),
}

/// The decision after `failures` (all runs of a task so far) with `retries` reruns allowed.
pub fn after_failure(failures: &[TaskFailure], retries: usize, time_limit: &str) -> AfterFailure {
    if failures.len() <= retries {
        return AfterFailure::Retry;
    }
    let runs = failures
        .iter()
        .map(|f| {
            if f.detail.is_empty() {
                f.state.clone()
            } else {
                format!("{} ({})", f.state, f.detail)
            }
        })
        .collect::<Vec<_>>()
        .join("; ");
    if failures.iter().all(|f| f.timed_out) {
        AfterFailure::TimeLimitTooShort(format!(
            "a task ran past the Slurm time limit ({time_limit}) on all {} runs: raise \
             [executor] time_limit (or --time-limit) above one task's simulation time",
            failures.len()
        ))
    } else {
        AfterFailure::RecordFailed(format!(
            "slurm task ended without a result {} times: {runs}",
            failures.len()
        ))
    }
}

/// One candidate's task while its batch runs.
struct Task {
    /// Index in the batch.
    index: usize,
    path: PathBuf,
    result: PathBuf,
    /// `(job id, array index)` of its current run (array mode).
    job: Option<(String, usize)>,
    /// Its running `srun` step (allocation mode).
    step: Option<Child>,
    /// Output file of its current run.
    output: PathBuf,
    failures: Vec<TaskFailure>,
    /// When its current run was first seen ended without a result.
    ended_at: Option<Instant>,
    ended_state: Option<(String, String)>,
    done: bool,
}

/// The Slurm executor.
pub struct SlurmExecutor {
    entry: ExecutorEntry,
    max_concurrent: usize,
    /// `<output>/slurm`, absolute.
    folder: PathBuf,
    campaign: PathBuf,
    campaign_sha256: String,
    stoss: PathBuf,
    job_name: String,
    submissions: usize,
    /// Array jobs with tasks not yet accounted for (cancelled if the coordinator stops on an
    /// error).
    active_jobs: BTreeSet<String>,
    /// The allocation's job id (allocation mode).
    allocation: Option<String>,
    quiet: bool,
    /// Results adopted from a killed run's tasks.
    pub adopted: usize,
}

impl SlurmExecutor {
    /// Set up in `output/slurm`: check the Slurm commands, write the worker scripts, take the
    /// allocation (allocation mode) and run the probe task.
    pub fn start(
        entry: &ExecutorEntry,
        max_concurrent: usize,
        campaign: &Campaign,
        output: &Path,
        quiet: bool,
    ) -> Result<Self, ExecutorError> {
        entry
            .check()
            .map_err(|(field, message)| executor_error(format!("[executor] {field}: {message}")))?;
        let needed: &[&str] = match entry.mode {
            SlurmMode::Array => &["sbatch", "squeue", "scancel"],
            SlurmMode::Allocation => &["salloc", "srun", "scancel"],
        };
        for program in needed {
            if on_path(program).is_none() {
                return Err(executor_error(format!(
                    "{program} is not on PATH: the slurm executor needs Slurm's client commands \
                     ({}); run on a login node of the cluster, or load its module",
                    needed.join(", ")
                )));
            }
        }
        let stoss = std::env::current_exe()
            .map_err(|e| executor_error(format!("the stoss binary's path: {e}")))?;
        let output = std::path::absolute(output)
            .map_err(|e| executor_error(format!("{}: {e}", output.display())))?;
        let folder = output.join("slurm");
        for sub in ["tasks", "submissions"] {
            std::fs::create_dir_all(folder.join(sub))
                .map_err(|e| executor_error(format!("{}: {e}", folder.join(sub).display())))?;
        }
        let campaign_path = campaign
            .path
            .canonicalize()
            .map_err(|e| executor_error(format!("{}: {e}", campaign.path.display())))?;
        let campaign_text = std::fs::read(&campaign_path)
            .map_err(|e| executor_error(format!("{}: {e}", campaign_path.display())))?;
        let submissions = std::fs::read_dir(folder.join("submissions"))
            .map(|entries| {
                entries
                    .filter_map(Result::ok)
                    .filter(|e| e.file_name().to_string_lossy().ends_with(".list"))
                    .count()
            })
            .unwrap_or(0);
        let mut executor = Self {
            entry: entry.clone(),
            max_concurrent: max_concurrent.max(1),
            folder,
            campaign: campaign_path,
            campaign_sha256: sha256_hex(&campaign_text),
            stoss,
            job_name: format!(
                "stoss-{}",
                &sha256_hex(output.to_string_lossy().as_bytes())[..8]
            ),
            submissions,
            active_jobs: BTreeSet::new(),
            allocation: None,
            quiet,
            adopted: 0,
        };
        executor.write_scripts()?;
        if entry.mode == SlurmMode::Allocation {
            executor.allocate()?;
        }
        executor.probe()?;
        Ok(executor)
    }

    fn say(&self, message: &str) {
        if !self.quiet {
            eprintln!("slurm: {message}");
        }
    }

    /// The worker scripts: `array.sh LIST` runs line SLURM_ARRAY_TASK_ID + 1 of LIST;
    /// `step.sh TASK` runs one task; `probe.sh FILE` writes the probe. Each runs the prologue
    /// first.
    fn write_scripts(&self) -> Result<(), ExecutorError> {
        // The workers load the campaign as the coordinator did: with --force if it was given.
        let stoss = format!(
            "{}{}",
            shell_quote(&self.stoss.to_string_lossy()),
            if crate::input::implausible_allowed() {
                " --force"
            } else {
                ""
            }
        );
        let threads = self.entry.cpus_per_task;
        let prologue: String = self
            .entry
            .prologue
            .iter()
            .map(|line| format!("{line}\n"))
            .collect();
        let header = "#!/bin/sh\n# Written by stoss (Slurm executor); runs one task of a \
                      calibration or diagnosis.\n";
        let scripts = [
            (
                "array.sh",
                format!(
                    "{header}{prologue}task=$(sed -n \"$((SLURM_ARRAY_TASK_ID + 1))p\" \"$1\")\n\
                     exec {stoss} evaluate --threads {threads} \"$task\"\n"
                ),
            ),
            (
                "step.sh",
                format!("{header}{prologue}exec {stoss} evaluate --threads {threads} \"$1\"\n"),
            ),
            (
                "probe.sh",
                format!("{header}{prologue}exec {stoss} evaluate --probe \"$1\"\n"),
            ),
        ];
        for (name, text) in scripts {
            let path = self.folder.join(name);
            write_atomically(&path, text.as_bytes())
                .map_err(|e| executor_error(format!("{}: {e}", path.display())))?;
            #[cfg(unix)]
            {
                use std::os::unix::fs::PermissionsExt as _;
                std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755))
                    .map_err(|e| executor_error(format!("{}: {e}", path.display())))?;
            }
        }
        Ok(())
    }

    /// Arguments shared by sbatch, salloc and srun: job name, partition, extra arguments.
    fn common_args(&self) -> Vec<String> {
        let mut args = vec![format!("--job-name={}", self.job_name)];
        if let Some(partition) = &self.entry.partition {
            args.push(format!("--partition={partition}"));
        }
        args
    }

    fn time_limit_text(&self) -> String {
        self.entry
            .time_limit
            .clone()
            .unwrap_or_else(|| "the partition's limit".into())
    }

    /// Allocation mode: take the allocation (`salloc --no-shell`), waiting at most the probe
    /// timeout for it.
    fn allocate(&mut self) -> Result<(), ExecutorError> {
        let mut args = self.common_args();
        args.push("--no-shell".into());
        args.push(format!("--ntasks={}", self.max_concurrent));
        args.push(format!("--cpus-per-task={}", self.entry.cpus_per_task));
        args.push(format!(
            "--immediate={}",
            self.entry.probe_timeout.ceil().max(1.0) as u64
        ));
        if let Some(limit) = &self.entry.allocation_time_limit {
            args.push(format!("--time={limit}"));
        }
        args.extend(self.entry.sbatch_args.iter().cloned());
        self.say(&format!(
            "waiting for an allocation of {} tasks",
            self.max_concurrent
        ));
        let output = Command::new("salloc")
            .args(&args)
            .stdin(Stdio::null())
            .output()
            .map_err(|e| executor_error(format!("salloc: {e}")))?;
        let stderr = String::from_utf8_lossy(&output.stderr);
        let job = stderr
            .split("Granted job allocation")
            .nth(1)
            .and_then(|rest| rest.split_whitespace().next())
            .filter(|id| id.bytes().all(|b| b.is_ascii_digit()));
        match (output.status.success(), job) {
            (true, Some(job)) => {
                self.say(&format!("holding allocation {job}"));
                self.allocation = Some(job.to_string());
                Ok(())
            }
            _ => Err(executor_error(format!(
                "salloc did not grant an allocation ({}): {}",
                output.status,
                stderr.trim()
            ))),
        }
    }

    /// Run the probe and check its answer: same binary, visible run folder.
    fn probe(&mut self) -> Result<(), ExecutorError> {
        let attempt = self.submissions;
        let answer = self.folder.join(format!("probe-{attempt}.json"));
        let output = self
            .folder
            .join("submissions")
            .join(format!("probe-{attempt}.out"));
        let _ = std::fs::remove_file(&answer);
        let probe_script = self.folder.join("probe.sh").to_string_lossy().into_owned();
        let deadline = Instant::now() + Duration::from_secs_f64(self.entry.probe_timeout);
        let mut step: Option<Child> = None;
        let mut job: Option<String> = None;
        match &self.allocation {
            Some(allocation) => {
                let log = std::fs::File::create(&output)
                    .map_err(|e| executor_error(format!("{}: {e}", output.display())))?;
                let child = Command::new("srun")
                    .args([
                        format!("--jobid={allocation}"),
                        "--ntasks=1".into(),
                        "--nodes=1".into(),
                        "--cpus-per-task=1".into(),
                        "--exact".into(),
                        probe_script,
                        answer.to_string_lossy().into_owned(),
                    ])
                    .stdin(Stdio::null())
                    .stdout(log.try_clone().map_err(|e| executor_error(e.to_string()))?)
                    .stderr(log)
                    .spawn()
                    .map_err(|e| executor_error(format!("srun: {e}")))?;
                step = Some(child);
            }
            None => {
                let mut args = vec!["--parsable".to_string()];
                args.extend(self.common_args());
                args.push(format!("--output={}", output.display()));
                args.push("--ntasks=1".into());
                args.push("--cpus-per-task=1".into());
                if let Some(limit) = &self.entry.time_limit {
                    args.push(format!("--time={limit}"));
                }
                args.extend(self.entry.sbatch_args.iter().cloned());
                args.push(probe_script);
                args.push(answer.to_string_lossy().into_owned());
                let id = run_command("sbatch", &args)
                    .map_err(|e| executor_error(format!("sbatch rejected the probe job: {e}")))?;
                let id = id.trim().split(';').next().unwrap_or_default().to_string();
                self.say(&format!("probe job {id} submitted"));
                job = Some(id);
            }
        }
        let mut ended_at: Option<Instant> = None;
        let outcome = loop {
            if answer.exists() {
                break Ok(());
            }
            let now = Instant::now();
            if now > deadline {
                break Err(format!(
                    "the probe task gave no answer within probe_timeout = {} s (still queued, \
                     or the run folder {} is not visible to the compute nodes)",
                    self.entry.probe_timeout,
                    self.folder.display()
                ));
            }
            let ended = match (&mut step, &job) {
                (Some(child), _) => child.try_wait().ok().flatten().is_some(),
                (None, Some(id)) => self.queue_states().ok().is_some_and(|states| {
                    !states.keys().any(|(j, _)| j == id)
                        || states
                            .iter()
                            .any(|((j, _), (s, _))| j == id && ENDED_STATES.contains(&s.as_str()))
                }),
                (None, None) => true,
            };
            if ended {
                let first = *ended_at.get_or_insert(now);
                if now.duration_since(first).as_secs_f64() > self.entry.result_wait {
                    break Err(format!(
                        "the probe task ended, but its answer {} did not appear here within \
                         result_wait = {} s: the run folder must be on a filesystem the compute \
                         nodes share with this machine (its output: {})",
                        answer.display(),
                        self.entry.result_wait,
                        tail_of(&output, 5)
                    ));
                }
            }
            std::thread::sleep(Duration::from_secs_f64(self.entry.poll_interval));
        };
        if let Some(mut child) = step {
            if outcome.is_err() {
                let _ = child.kill();
            }
            let _ = child.wait();
        }
        if let (Err(_), Some(id)) = (&outcome, &job) {
            let _ = run_command("scancel", std::slice::from_ref(id));
        }
        outcome.map_err(executor_error)?;
        let text = std::fs::read_to_string(&answer)
            .map_err(|e| executor_error(format!("{}: {e}", answer.display())))?;
        let origin: Origin = serde_json::from_str(&text)
            .map_err(|e| executor_error(format!("{}: {e}", answer.display())))?;
        if origin.binary_sha256 != binary_sha256() {
            return Err(executor_error(format!(
                "the workers run a different stoss binary (SHA-256 {} on {}, {} here): {} must \
                 be the same file on the compute nodes",
                origin.binary_sha256,
                origin.host,
                binary_sha256(),
                self.stoss.display()
            )));
        }
        self.say(&format!(
            "probe answered from {} (same stoss binary, run folder shared)",
            origin.host
        ));
        Ok(())
    }

    /// States of this run's tasks in the queue: `(job id, array index) -> (state, reason)`;
    /// a job that is not an array has index 0.
    fn queue_states(&self) -> Result<QueueStates, String> {
        let text = run_command(
            "squeue",
            &[
                "--noheader".into(),
                "--array".into(),
                "--states=all".into(),
                format!("--name={}", self.job_name),
                "--format=%F|%K|%T|%r".into(),
            ],
        )?;
        let mut states = BTreeMap::new();
        for line in text.lines() {
            let fields: Vec<&str> = line.trim().split('|').collect();
            if let [job, index, state, reason] = fields.as_slice() {
                let index = index.parse().unwrap_or(0);
                states.insert(
                    (job.to_string(), index),
                    (state.to_string(), reason.to_string()),
                );
            }
        }
        Ok(states)
    }

    /// Submit `tasks` as one job array.
    fn submit_array(&mut self, tasks: &mut [&mut Task]) -> Result<(), ExecutorError> {
        let number = self.submissions;
        self.submissions += 1;
        let submissions = self.folder.join("submissions");
        let list = submissions.join(format!("{number}.list"));
        let lines: String = tasks
            .iter()
            .map(|t| format!("{}\n", t.path.display()))
            .collect();
        write_atomically(&list, lines.as_bytes())
            .map_err(|e| executor_error(format!("{}: {e}", list.display())))?;
        let mut args = vec!["--parsable".to_string()];
        args.extend(self.common_args());
        args.push(format!(
            "--array=0-{}%{}",
            tasks.len() - 1,
            self.max_concurrent
        ));
        args.push(format!(
            "--output={}",
            submissions.join(format!("{number}-%a.out")).display()
        ));
        args.push("--ntasks=1".into());
        args.push(format!("--cpus-per-task={}", self.entry.cpus_per_task));
        if let Some(limit) = &self.entry.time_limit {
            args.push(format!("--time={limit}"));
        }
        args.extend(self.entry.sbatch_args.iter().cloned());
        args.push(self.folder.join("array.sh").to_string_lossy().into_owned());
        args.push(list.to_string_lossy().into_owned());
        let id = run_command("sbatch", &args)
            .map_err(|e| executor_error(format!("sbatch rejected the job array: {e}")))?;
        let id = id.trim().split(';').next().unwrap_or_default().to_string();
        for (array_index, task) in tasks.iter_mut().enumerate() {
            task.job = Some((id.clone(), array_index));
            task.output = submissions.join(format!("{number}-{array_index}.out"));
            task.ended_at = None;
            task.ended_state = None;
        }
        self.active_jobs.insert(id);
        Ok(())
    }

    /// Start one task as an `srun` step of the allocation.
    fn start_step(&mut self, task: &mut Task) -> Result<(), ExecutorError> {
        let allocation = self.allocation.clone().unwrap_or_default();
        let number = self.submissions;
        self.submissions += 1;
        let submissions = self.folder.join("submissions");
        // A `.list` per step keeps the numbering of a resumed run unique.
        let list = submissions.join(format!("{number}.list"));
        write_atomically(&list, format!("{}\n", task.path.display()).as_bytes())
            .map_err(|e| executor_error(format!("{}: {e}", list.display())))?;
        task.output = submissions.join(format!("{number}.out"));
        let log = std::fs::File::create(&task.output)
            .map_err(|e| executor_error(format!("{}: {e}", task.output.display())))?;
        let mut args = vec![
            format!("--jobid={allocation}"),
            "--ntasks=1".into(),
            "--nodes=1".into(),
            format!("--cpus-per-task={}", self.entry.cpus_per_task),
            "--exact".into(),
        ];
        if let Some(limit) = &self.entry.time_limit {
            args.push(format!("--time={limit}"));
        }
        args.push(self.folder.join("step.sh").to_string_lossy().into_owned());
        args.push(task.path.to_string_lossy().into_owned());
        let child = Command::new("srun")
            .args(&args)
            .stdin(Stdio::null())
            .stdout(log.try_clone().map_err(|e| executor_error(e.to_string()))?)
            .stderr(log)
            .spawn()
            .map_err(|e| executor_error(format!("srun: {e}")))?;
        task.step = Some(child);
        task.job = Some((allocation, number));
        task.ended_at = None;
        task.ended_state = None;
        Ok(())
    }

    /// Read and check a task's result file.
    fn read_result<W: Work>(&self, work: &W, task: &Task) -> Option<(W::Output, Origin)> {
        let text = std::fs::read_to_string(&task.result).ok()?;
        work.read_result(task.index, &text)
    }
}

impl Drop for SlurmExecutor {
    fn drop(&mut self) {
        // Reached when the calibration ends or stops on an error (not when the process is
        // killed: then the tasks go on, and a resumed run adopts their results).
        let jobs: Vec<String> = self
            .active_jobs
            .iter()
            .cloned()
            .chain(self.allocation.clone())
            .collect();
        if !jobs.is_empty() {
            let _ = run_command("scancel", &jobs);
        }
    }
}

/// One batch on the cluster: its tasks, the results so far, the tasks due to (re)start, and
/// when the queue was last read and the waiting tasks last reported.
struct BatchRun<O> {
    tasks: Vec<Task>,
    results: Vec<Option<O>>,
    to_start: Vec<usize>,
    queue_unreadable_since: Option<Instant>,
    last_queue_read: Option<Instant>,
    last_waiting_report: Instant,
}

/// How a task's run ended, if it did (state, reason), without a result so far.
fn ended_run(
    task: &mut Task,
    states: &Option<QueueStates>,
    waiting: &mut BTreeMap<String, usize>,
) -> Option<(String, String)> {
    match (&mut task.step, states) {
        (Some(child), _) => match child.try_wait() {
            Ok(Some(status)) => Some((format!("step {status}"), String::new())),
            Ok(None) => None,
            Err(e) => Some(("step lost".into(), e.to_string())),
        },
        (None, Some(states)) => {
            let job = task.job.clone().unwrap_or_default();
            match states.get(&job) {
                None => Some(("left the queue".into(), String::new())),
                Some((state, reason)) if ENDED_STATES.contains(&state.as_str()) => {
                    Some((state.clone(), reason.clone()))
                }
                Some((state, reason)) => {
                    if state == "PENDING" {
                        *waiting.entry(reason.clone()).or_default() += 1;
                    }
                    None
                }
            }
        }
        // The queue was not read this time: keep what is known.
        (None, None) => task.ended_state.clone(),
    }
}

impl SlurmExecutor {
    /// The executor name results record.
    fn executor_name(&self) -> &'static str {
        match self.entry.mode {
            SlurmMode::Array => "slurm-array",
            SlurmMode::Allocation => "slurm-allocation",
        }
    }

    /// The batch's tasks: a result a task of a killed coordinator wrote is adopted, every
    /// other item gets a fresh task file.
    fn prepare<W: Work>(&mut self, work: &W) -> Result<BatchRun<W::Output>, ExecutorError> {
        let mut results: Vec<Option<W::Output>> = vec![None; work.len()];
        let mut tasks: Vec<Task> = Vec::with_capacity(work.len());
        for (index, result) in results.iter_mut().enumerate() {
            let name = work.task_name(index);
            let path = self.folder.join("tasks").join(format!("{name}.task.json"));
            let mut task = Task {
                index,
                result: result_path(&path),
                path,
                job: None,
                step: None,
                output: PathBuf::new(),
                failures: Vec::new(),
                ended_at: None,
                ended_state: None,
                done: false,
            };
            if let Some((output, origin)) = self.read_result(work, &task) {
                work.record(index, &output, &origin)?;
                *result = Some(output);
                task.done = true;
                self.adopted += 1;
            } else {
                let _ = std::fs::remove_file(&task.result);
                let json = work.task_json(index, self).map_err(executor_error)?;
                write_atomically(&task.path, &json)
                    .map_err(|e| executor_error(format!("{}: {e}", task.path.display())))?;
            }
            tasks.push(task);
        }
        let adopted = tasks.iter().filter(|t| t.done).count();
        if adopted > 0 {
            self.say(&format!(
                "{adopted} result(s) adopted from tasks that finished after the coordinator stopped"
            ));
        }
        let to_start: Vec<usize> = (0..tasks.len()).filter(|&i| !tasks[i].done).collect();
        Ok(BatchRun {
            tasks,
            results,
            to_start,
            queue_unreadable_since: None,
            last_queue_read: None,
            last_waiting_report: Instant::now(),
        })
    }

    /// Start what is due: a job array of every task to (re)run, or steps up to the
    /// concurrency limit.
    fn start_due<O>(&mut self, run: &mut BatchRun<O>) -> Result<(), ExecutorError> {
        match self.entry.mode {
            SlurmMode::Array => {
                if !run.to_start.is_empty() {
                    let to_start = std::mem::take(&mut run.to_start);
                    let mut starting: Vec<&mut Task> = run
                        .tasks
                        .iter_mut()
                        .filter(|t| to_start.contains(&t.index))
                        .collect();
                    self.submit_array(&mut starting)?;
                }
            }
            SlurmMode::Allocation => {
                let running = run.tasks.iter().filter(|t| t.step.is_some()).count();
                let free = self.max_concurrent.saturating_sub(running);
                let due: Vec<usize> = run.to_start.drain(..free.min(run.to_start.len())).collect();
                for index in due {
                    self.start_step(&mut run.tasks[index])?;
                }
            }
        }
        Ok(())
    }

    /// Record the results that have arrived.
    fn collect_arrived<W: Work>(
        &self,
        work: &W,
        run: &mut BatchRun<W::Output>,
    ) -> Result<(), ExecutorError> {
        for task in run.tasks.iter_mut().filter(|t| !t.done && t.job.is_some()) {
            if let Some((output, mut origin)) = self.read_result(work, task) {
                origin.attempts = task.failures.len() as u32 + 1;
                work.record(task.index, &output, &origin)?;
                run.results[task.index] = Some(output);
                task.done = true;
                if let Some(mut child) = task.step.take() {
                    let _ = child.wait();
                }
            }
        }
        Ok(())
    }

    /// The queue's states (job arrays, at most every [`QUEUE_READ_INTERVAL`]); an error when
    /// it has been unreadable for [`QUEUE_UNREADABLE_LIMIT`].
    fn read_queue<O>(
        &self,
        run: &mut BatchRun<O>,
        now: Instant,
        poll: Duration,
    ) -> Result<Option<QueueStates>, ExecutorError> {
        let queue_due = run
            .last_queue_read
            .is_none_or(|t: Instant| now.duration_since(t) >= QUEUE_READ_INTERVAL.max(poll));
        Ok(match self.entry.mode {
            SlurmMode::Array if !queue_due => None,
            SlurmMode::Array => match self.queue_states() {
                Ok(states) => {
                    run.queue_unreadable_since = None;
                    run.last_queue_read = Some(now);
                    Some(states)
                }
                Err(error) => {
                    let since = *run.queue_unreadable_since.get_or_insert(now);
                    if now.duration_since(since) > QUEUE_UNREADABLE_LIMIT {
                        return Err(executor_error(format!(
                            "the queue could not be read for {} s: {error}",
                            QUEUE_UNREADABLE_LIMIT.as_secs()
                        )));
                    }
                    None
                }
            },
            SlurmMode::Allocation => None,
        })
    }

    /// A run that ended without a result within the wait: booked as a failure, then rerun,
    /// recorded as a failed candidate, or (time limit too short) the batch's error.
    fn after_failed_run<W: Work>(
        &self,
        work: &W,
        task: &mut Task,
        to_start: &mut Vec<usize>,
        results: &mut [Option<W::Output>],
    ) -> Result<(), ExecutorError> {
        let (state, reason) = task.ended_state.take().unwrap_or_default();
        let output_tail = tail_of(&task.output, 3);
        let timed_out = state == "TIMEOUT" || output_tail.contains("DUE TO TIME LIMIT");
        let detail = [reason, output_tail]
            .into_iter()
            .filter(|s| !s.is_empty() && s != "None")
            .collect::<Vec<_>>()
            .join("; ");
        task.failures.push(TaskFailure {
            state,
            detail,
            timed_out,
        });
        task.job = None;
        task.step = None;
        task.ended_at = None;
        match after_failure(&task.failures, self.entry.retries, &self.time_limit_text()) {
            AfterFailure::Retry => {
                let last = task
                    .failures
                    .last()
                    .map_or(String::new(), |f| f.state.clone());
                if !self.quiet {
                    eprintln!(
                        "slurm: task {} ended without a result ({last}); rerun {} of {}",
                        task.path.display(),
                        task.failures.len(),
                        self.entry.retries
                    );
                }
                to_start.push(task.index);
            }
            AfterFailure::RecordFailed(reason) => {
                let output = work.failed(task.index, reason);
                let mut origin = Origin::this_process(self.executor_name());
                origin.attempts = task.failures.len() as u32;
                work.record(task.index, &output, &origin)?;
                results[task.index] = Some(output);
                task.done = true;
            }
            AfterFailure::TimeLimitTooShort(message) => {
                return Err(executor_error(message));
            }
        }
        Ok(())
    }

    /// Runs that ended without a result: failed once the result wait has passed; and the
    /// pending tasks' reasons, reported every [`WAITING_REPORT_INTERVAL`].
    fn check_ended<W: Work>(
        &self,
        work: &W,
        run: &mut BatchRun<W::Output>,
        poll: Duration,
    ) -> Result<(), ExecutorError> {
        let now = Instant::now();
        let states = self.read_queue(run, now, poll)?;
        let mut waiting: BTreeMap<String, usize> = BTreeMap::new();
        let BatchRun {
            tasks,
            results,
            to_start,
            ..
        } = run;
        for task in tasks.iter_mut().filter(|t| !t.done && t.job.is_some()) {
            let Some(ended) = ended_run(task, &states, &mut waiting) else {
                task.ended_at = None;
                continue;
            };
            task.ended_state.get_or_insert(ended);
            let first = *task.ended_at.get_or_insert(now);
            if now.duration_since(first).as_secs_f64() < self.entry.result_wait {
                continue;
            }
            self.after_failed_run(work, task, to_start, results)?;
        }
        if !waiting.is_empty()
            && now.duration_since(run.last_waiting_report) >= WAITING_REPORT_INTERVAL
        {
            run.last_waiting_report = now;
            let reasons: Vec<String> = waiting.iter().map(|(r, n)| format!("{n} ({r})")).collect();
            self.say(&format!(
                "tasks waiting in the queue: {}",
                reasons.join(", ")
            ));
        }
        Ok(())
    }
}

impl SlurmExecutor {
    /// Run every item of `work` as a task, recording each result as it arrives; the outputs
    /// in the batch's order.
    fn run_batch<W: Work>(&mut self, work: &W) -> Result<Vec<W::Output>, ExecutorError> {
        let mut run = self.prepare(work)?;
        let poll = Duration::from_secs_f64(self.entry.poll_interval);
        let outcome = (|| -> Result<(), ExecutorError> {
            loop {
                self.start_due(&mut run)?;
                if run.tasks.iter().all(|t| t.done) {
                    return Ok(());
                }
                std::thread::sleep(poll);
                self.collect_arrived(work, &mut run)?;
                self.check_ended(work, &mut run, poll)?;
            }
        })();
        // Steps still running when the batch stops on an error.
        for task in &mut run.tasks {
            if let Some(mut child) = task.step.take() {
                let _ = child.kill();
                let _ = child.wait();
            }
        }
        outcome?;
        // Every task of this batch is accounted for: its jobs need no cancelling.
        self.active_jobs.clear();
        run.results
            .into_iter()
            .map(|r| r.ok_or_else(|| executor_error("a task of the batch has no result")))
            .collect()
    }
}

impl Executor for SlurmExecutor {
    fn evaluate(
        &mut self,
        batch: &Batch<'_>,
        record: &Record<'_>,
    ) -> Result<Vec<Evaluation>, ExecutorError> {
        self.run_batch(&Candidates { batch, record })
    }

    fn predict(
        &mut self,
        batch: &PredictionBatch<'_>,
        record: &RecordPrediction<'_>,
    ) -> Result<Vec<Prediction>, ExecutorError> {
        self.run_batch(&Predictions { batch, record })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn failure(state: &str, timed_out: bool) -> TaskFailure {
        TaskFailure {
            state: state.into(),
            detail: String::new(),
            timed_out,
        }
    }

    #[test]
    fn failed_tasks_are_retried_then_recorded_or_stop_the_run() {
        // GOAL: a task that ends without a result is rerun up to `retries` times, then its
        // candidate is recorded as failed; a candidate that hit the time limit on every run
        // stops the calibration with an error naming the limit (not a hang, not a silent
        // failure). SETUP: failure histories with 2 retries allowed.
        // REFERENCE: the executor's stated policy.
        assert_eq!(
            after_failure(&[failure("CANCELLED", false)], 2, "1"),
            AfterFailure::Retry
        );
        let mixed = [
            failure("CANCELLED", false),
            failure("NODE_FAIL", false),
            failure("TIMEOUT", true),
        ];
        match after_failure(&mixed, 2, "00:10:00") {
            AfterFailure::RecordFailed(reason) => {
                assert!(
                    reason.contains("3 times") && reason.contains("NODE_FAIL"),
                    "{reason}"
                )
            }
            other => panic!("{other:?}"),
        }
        let timeouts = [failure("TIMEOUT", true), failure("TIMEOUT", true)];
        match after_failure(&timeouts, 1, "00:01:00") {
            AfterFailure::TimeLimitTooShort(message) => {
                assert!(message.contains("00:01:00") && message.contains("time_limit"))
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn shell_quoting_survives_quotes_and_spaces() {
        // GOAL: paths with spaces or quotes reach the worker intact.
        // SETUP: a path with both. REFERENCE: POSIX sh single quoting.
        assert_eq!(shell_quote("/a b/it's"), r"'/a b/it'\''s'");
    }
}
