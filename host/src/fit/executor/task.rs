//! Work outside the coordinating process: the task file a coordinator writes, the result file
//! a worker (`stoss evaluate`) writes back atomically (temporary file, then rename), and the
//! origin every result records (stoss version, binary hash, host), so that results computed on
//! other machines stay traceable. A task is one of two kinds:
//! - a calibration candidate ([`TaskFile`] -> [`ResultFile`]): a model's constants, scored on
//!   a campaign's experiments;
//! - a prediction job ([`PredictionTaskFile`] -> [`PredictionResultFile`]): a realised
//!   hypothesis of a least-squares fit (the material file with its values written in, the
//!   anvil friction, the lagged-rate mixture) simulated on one campaign experiment.

use super::super::campaign::Campaign;
use super::super::hypothesis::Realisation;
use super::super::log::Key;
use super::super::objective::{evaluate_at, Evaluation};
use crate::fit::ModelSpace;
use crate::solver::SolverSettings;
use serde::{Deserialize, Serialize};
use sha2::Digest as _;
use std::collections::BTreeMap;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Where and by what a result was computed.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Origin {
    /// stoss version.
    pub stoss_version: String,
    /// SHA-256 of the stoss binary that simulated (hex).
    pub binary_sha256: String,
    /// Host name of the machine that simulated.
    pub host: String,
    /// Executor: `local`, `slurm-array`, `slurm-allocation` or `probe`.
    pub executor: String,
    /// Slurm job (`job_task` of an array, `job.step` of an allocation), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slurm_job: Option<String>,
    /// Runs it took (1 = the first; more after failed, cancelled or lost tasks).
    #[serde(default = "one")]
    pub attempts: u32,
}

fn one() -> u32 {
    1
}

/// SHA-256 (hex) of this process's binary, computed once.
pub fn binary_sha256() -> &'static str {
    static HASH: OnceLock<String> = OnceLock::new();
    HASH.get_or_init(|| {
        std::env::current_exe()
            .and_then(std::fs::read)
            .map(|bytes| sha256_hex(&bytes))
            .unwrap_or_else(|_| "unknown".into())
    })
}

/// SHA-256 of `bytes`, as 64 hex digits.
pub fn sha256_hex(bytes: &[u8]) -> String {
    sha2::Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// This machine's host name (`/proc/sys/kernel/hostname`, else `$HOSTNAME`, else `unknown`).
pub fn host_name() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .or_else(|| std::env::var("HOSTNAME").ok())
        .unwrap_or_else(|| "unknown".into())
}

impl Origin {
    /// This process, as executor `executor`, first attempt.
    pub fn this_process(executor: &str) -> Self {
        Self {
            stoss_version: env!("CARGO_PKG_VERSION").into(),
            binary_sha256: binary_sha256().into(),
            host: host_name(),
            executor: executor.into(),
            slurm_job: None,
            attempts: 1,
        }
    }
}

/// One candidate to evaluate, as a coordinator writes it for a worker.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TaskFile {
    /// The campaign file (absolute path; its experiment and material paths are relative to it).
    pub campaign: PathBuf,
    /// SHA-256 of the campaign file's text when the calibration started.
    pub campaign_sha256: String,
    /// The model whose constants these are.
    pub model: String,
    /// The candidate's place in the calibration.
    pub key: Key,
    /// Its optimiser instance's seed.
    pub seed: u64,
    /// Campaign experiments to simulate (indices).
    pub experiments: Vec<usize>,
    /// The fitted constants by the campaign's names (SI); JSON numbers round-trip exactly.
    /// The worker places them in its model space's order by name, so a task cannot hand a
    /// value to the wrong constant.
    #[serde(default)]
    pub constants: BTreeMap<String, f64>,
    /// The constants by position (the model space's order), as task files written before
    /// 2026-11-28 carry them; read only when `constants` is empty.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub values: Vec<f64>,
    /// Executor name recorded in the origin (`slurm-array`, `slurm-allocation`).
    pub executor: String,
}

impl TaskFile {
    /// `values` (the model space's order) keyed by the space's names.
    pub fn named(space: &ModelSpace, values: &[f64]) -> BTreeMap<String, f64> {
        space
            .names
            .iter()
            .cloned()
            .zip(values.iter().copied())
            .collect()
    }

    /// The task's constants in `space`'s order: by name (every name of the space present,
    /// no other), or by position for an old task of the right length.
    pub fn values_for(&self, space: &ModelSpace) -> Result<Vec<f64>, String> {
        if self.constants.is_empty() {
            if self.values.len() == space.dimension() {
                return Ok(self.values.clone());
            }
            return Err(format!(
                "{} constants by position, model {:?} fits {}",
                self.values.len(),
                space.name,
                space.dimension()
            ));
        }
        if let Some(extra) = self
            .constants
            .keys()
            .find(|name| !space.names.contains(name))
        {
            return Err(format!(
                "constant `{extra}` is not fitted by model {:?} (it fits {})",
                space.name,
                space.names.join(", ")
            ));
        }
        space
            .names
            .iter()
            .map(|name| {
                self.constants.get(name).copied().ok_or_else(|| {
                    format!("constant `{name}` of model {:?} is missing", space.name)
                })
            })
            .collect()
    }
}

/// A worker's answer: the evaluation of one task and where it was computed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ResultFile {
    /// The task's key (checked against the task).
    pub key: Key,
    /// The evaluation (its `values` are the task's, bit for bit).
    pub evaluation: Evaluation,
    /// Where it ran.
    pub origin: Origin,
}

/// A realised hypothesis as a task carries it: every value the simulation depends on.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RealisationRecord {
    /// The material file with the hypothesis' values written in (SI; JSON numbers
    /// round-trip exactly).
    pub material: crate::input::material::MaterialFile,
    /// The anvil friction override of Taylor tests, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub anvil_friction: Option<f64>,
    /// The lagged-rate mixture weight.
    pub lagged_mixture: f64,
    /// The erosion intensity (already applied to `material`; recorded for the reader).
    pub erosion_intensity: f64,
    /// Set-up parameters, written into the experiments they name.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub setup: Vec<crate::fit::space::SetupValue>,
}

impl RealisationRecord {
    /// The record of `realisation`.
    pub fn of(realisation: &Realisation) -> Self {
        Self {
            material: realisation.file.clone(),
            anvil_friction: realisation.anvil_friction,
            lagged_mixture: realisation.lagged_mixture,
            erosion_intensity: realisation.erosion_intensity,
            setup: realisation.setup.clone(),
        }
    }

    /// The realisation again: the kernel material built from the file, as the coordinator
    /// built it.
    pub fn realisation(&self) -> Result<Realisation, String> {
        let material = self.material.material().map_err(|e| e.to_string())?;
        Ok(Realisation {
            file: self.material.clone(),
            material,
            anvil_friction: self.anvil_friction,
            lagged_mixture: self.lagged_mixture,
            erosion_intensity: self.erosion_intensity,
            setup: self.setup.clone(),
        })
    }
}

/// One prediction job of a least-squares fit, as a coordinator writes it for a worker.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PredictionTaskFile {
    /// The campaign file (absolute path; its experiment paths are relative to it).
    pub campaign: PathBuf,
    /// SHA-256 of the campaign file's text when the run started.
    pub campaign_sha256: String,
    /// The job's journal key (checked against the result).
    pub key: String,
    /// The campaign experiment to simulate (index).
    pub experiment: usize,
    /// The material and settings to simulate with.
    pub realisation: RealisationRecord,
    /// Executor name recorded in the origin (`slurm-array`, `slurm-allocation`).
    pub executor: String,
}

/// A worker's answer to a prediction task.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PredictionResultFile {
    /// The task's key.
    pub key: String,
    /// The predictions (the recording's points), if the simulation succeeded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub predicted: Option<Vec<f64>>,
    /// Why the simulation failed, if it did.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Where it ran.
    pub origin: Origin,
}

impl PredictionResultFile {
    /// The prediction it carries.
    pub fn prediction(&self) -> super::Prediction {
        match (&self.predicted, &self.error) {
            (Some(p), _) => Ok(p.clone()),
            (None, Some(e)) => Err(e.clone()),
            (None, None) => Err("the result file holds neither predictions nor an error".into()),
        }
    }
}

/// A file name for the prediction task of journal key `key` (stable across runs).
pub fn prediction_task_name(key: &str) -> String {
    let key: String = key
        .chars()
        .filter(char::is_ascii_alphanumeric)
        .take(32)
        .collect();
    format!("predict-{key}")
}

/// The result file of a task file: `<name>.task.json` -> `<name>.result.json`.
pub fn result_path(task: &Path) -> PathBuf {
    let name = task
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let stem = name.strip_suffix(".task.json").unwrap_or(&name);
    task.with_file_name(format!("{stem}.result.json"))
}

/// A file name for the task of `key`: the model and a 64-bit FNV-1a hash of the key, stable
/// across runs (a resumed run finds the results of its tasks by it).
pub fn task_name(key: &Key) -> String {
    let hash = crate::hash::fnv1a(&serde_json::to_string(key).unwrap_or_default());
    let model: String = key
        .model
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .take(32)
        .collect();
    format!("{model}-{}-{hash:016x}", key.instance)
}

/// Write `bytes` to `path` atomically: a temporary file in the same folder (named by host and
/// process, so that two workers never share one), synced, then renamed over `path`.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let name = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let temporary = path.with_file_name(format!(
        ".{name}.{}.{}.tmp",
        host_name(),
        std::process::id()
    ));
    let result = (|| {
        let mut file = std::fs::File::create(&temporary)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        std::fs::rename(&temporary, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    result
}

/// Run a task file (the worker side of `stoss evaluate`): check the campaign is the one the
/// coordinator started from, simulate the candidate with `threads` solver threads, and write
/// the result file atomically. A candidate whose simulations fail is a result (status
/// `failed`), not an error; errors are a task that cannot be run at all.
pub fn run_task(task_path: &Path, threads: usize) -> Result<PathBuf, String> {
    let text =
        std::fs::read_to_string(task_path).map_err(|e| format!("{}: {e}", task_path.display()))?;
    let settings = SolverSettings {
        threads: Some(threads),
        ..SolverSettings::default()
    };
    // A prediction task is the one kind that carries a realisation.
    let is_prediction = serde_json::from_str::<serde_json::Value>(&text)
        .ok()
        .is_some_and(|v| v.get("realisation").is_some());
    if is_prediction {
        return run_prediction_task(task_path, &text, &settings);
    }
    let task: TaskFile =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", task_path.display()))?;
    let campaign = load_campaign(task_path, &task.campaign, &task.campaign_sha256)?;
    let model = campaign.model(&task.model).ok_or_else(|| {
        format!(
            "{}: model {:?} is not in {}",
            task_path.display(),
            task.model,
            task.campaign.display()
        )
    })?;
    let space = campaign.space(model);
    let values = task
        .values_for(&space)
        .map_err(|e| format!("{}: {e}", task_path.display()))?;
    if task.experiments.is_empty() {
        return Err(format!(
            "{}: the task names no experiment to simulate (an evaluation of nothing would \
             report `ok`)",
            task_path.display()
        ));
    }
    if task
        .experiments
        .iter()
        .any(|&i| i >= campaign.experiments.len())
    {
        return Err(format!(
            "{}: experiments {:?} are not all in the campaign ({} experiments)",
            task_path.display(),
            task.experiments,
            campaign.experiments.len()
        ));
    }
    let evaluation = evaluate_at(
        &campaign,
        &space,
        &values,
        &task.experiments,
        &settings,
        task.key.fidelity,
    );
    let mut origin = Origin::this_process(&task.executor);
    origin.slurm_job = slurm_job_of_environment();
    let result = ResultFile {
        key: task.key,
        evaluation,
        origin,
    };
    let path = result_path(task_path);
    let json = serde_json::to_vec(&result).map_err(|e| e.to_string())?;
    write_atomically(&path, &json).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(path)
}

/// The campaign a task names, checked to be the one the coordinator started from.
fn load_campaign(task_path: &Path, campaign: &Path, sha256: &str) -> Result<Campaign, String> {
    let campaign_text = std::fs::read(campaign).map_err(|e| {
        format!(
            "{} (campaign of {}): {e}",
            campaign.display(),
            task_path.display()
        )
    })?;
    if sha256_hex(&campaign_text) != sha256 {
        return Err(format!(
            "{}: the campaign file changed since the run started (its SHA-256 differs from the \
             task's); restart the run",
            campaign.display()
        ));
    }
    Campaign::load(campaign).map_err(|e| e.to_string())
}

/// Run a prediction task: simulate the realisation on the task's experiment and write the
/// result file atomically. A failed simulation is a result (its error), not an error.
fn run_prediction_task(
    task_path: &Path,
    text: &str,
    settings: &SolverSettings,
) -> Result<PathBuf, String> {
    let task: PredictionTaskFile =
        serde_json::from_str(text).map_err(|e| format!("{}: {e}", task_path.display()))?;
    let campaign = load_campaign(task_path, &task.campaign, &task.campaign_sha256)?;
    let experiment = campaign.experiments.get(task.experiment).ok_or_else(|| {
        format!(
            "{}: experiment {} is not in the campaign ({} experiments)",
            task_path.display(),
            task.experiment,
            campaign.experiments.len()
        )
    })?;
    let prediction = task
        .realisation
        .realisation()
        .and_then(|r| r.predict(experiment, settings));
    let mut origin = Origin::this_process(&task.executor);
    origin.slurm_job = slurm_job_of_environment();
    let result = PredictionResultFile {
        key: task.key,
        predicted: prediction.as_ref().ok().cloned(),
        error: prediction.err(),
        origin,
    };
    let path = result_path(task_path);
    let json = serde_json::to_vec(&result).map_err(|e| e.to_string())?;
    write_atomically(&path, &json).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(path)
}

/// The Slurm job of this process, from the environment Slurm sets: `job_task` in an array,
/// `job.step` in a step, `job` otherwise.
pub fn slurm_job_of_environment() -> Option<String> {
    let var = |name: &str| std::env::var(name).ok().filter(|v| !v.is_empty());
    if let (Some(array), Some(task)) = (var("SLURM_ARRAY_JOB_ID"), var("SLURM_ARRAY_TASK_ID")) {
        return Some(format!("{array}_{task}"));
    }
    let job = var("SLURM_JOB_ID")?;
    Some(match var("SLURM_STEP_ID") {
        Some(step) => format!("{job}.{step}"),
        None => job,
    })
}

/// The probe (`stoss evaluate --probe FILE`): write this process's origin to `path`
/// atomically, so the coordinator learns that workers run the same binary and see the run
/// folder.
pub fn write_probe(path: &Path) -> Result<(), String> {
    let mut origin = Origin::this_process("probe");
    origin.slurm_job = slurm_job_of_environment();
    let json = serde_json::to_vec(&origin).map_err(|e| e.to_string())?;
    write_atomically(path, &json).map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn task_names_are_stable_and_distinct() {
        // GOAL: a resumed run finds its tasks' results under the same names; distinct keys get
        // distinct names. SETUP: keys differing in fold, instance and index.
        // REFERENCE: FNV-1a of the key's JSON (fixed constants, so the names never change).
        let key = |fold: Option<&str>, instance, index| Key {
            model: "jc/2".into(),
            fold: fold.map(str::to_string),
            instance,
            index,
            fidelity: Default::default(),
        };
        let a = task_name(&key(None, 0, 3));
        assert_eq!(a, task_name(&key(None, 0, 3)));
        assert!(a.starts_with("jc_2-0-"), "{a}");
        let names = [
            a,
            task_name(&key(Some("x.toml"), 0, 3)),
            task_name(&key(None, 1, 3)),
            task_name(&key(None, 0, 4)),
        ];
        for (i, n) in names.iter().enumerate() {
            assert!(names[i + 1..].iter().all(|m| m != n));
        }
        assert_eq!(
            result_path(Path::new("/r/t/jc-0-00ff.task.json")),
            Path::new("/r/t/jc-0-00ff.result.json")
        );
    }

    #[test]
    fn task_constants_are_placed_by_name_and_old_positional_tasks_still_read() {
        // GOAL: a task file carries its constants by name (issue 49); the worker places them
        //       in its space's order whatever order the file holds, refuses a missing or an
        //       unknown name, and still reads a task written before (positional `values`).
        // SETUP: a space fitting A and C; a task written for it, read back as JSON; a task
        //        text with the names in the other order; one missing C; one naming B; an old
        //        positional task of two values and one of three.
        // REFERENCE: [1.5e9, 0.02] in the space's order; errors naming the constant.
        let space = ModelSpace {
            setup: Vec::new(),
            name: "jc".into(),
            strength: None,
            names: vec!["yield_stress".into(), "rate_sensitivity".into()],
            lower: vec![0.0; 2],
            upper: vec![1.0; 2],
        };
        let task = TaskFile {
            campaign: "c.toml".into(),
            campaign_sha256: "0".into(),
            model: "jc".into(),
            key: Key {
                model: "jc".into(),
                fold: None,
                instance: 0,
                index: 0,
                fidelity: Default::default(),
            },
            seed: 1,
            experiments: vec![0],
            constants: TaskFile::named(&space, &[1.5e9, 0.02]),
            values: Vec::new(),
            executor: "slurm-array".into(),
        };
        let json = serde_json::to_string(&task).unwrap();
        assert!(json.contains("\"yield_stress\":1500000000.0"), "{json}");
        assert!(!json.contains("\"values\""), "{json}");
        let read: TaskFile = serde_json::from_str(&json).unwrap();
        assert_eq!(read.values_for(&space).unwrap(), vec![1.5e9, 0.02]);
        let with = |constants: &str| -> TaskFile {
            let text = json.replace(
                "\"constants\":{\"rate_sensitivity\":0.02,\"yield_stress\":1500000000.0}",
                constants,
            );
            assert_ne!(text, json, "the replacement must apply");
            serde_json::from_str(&text).unwrap()
        };
        let swapped = with("\"constants\":{\"yield_stress\":1.5e9,\"rate_sensitivity\":0.02}");
        assert_eq!(swapped.values_for(&space).unwrap(), vec![1.5e9, 0.02]);
        let missing = with("\"constants\":{\"yield_stress\":1.5e9}");
        let error = missing.values_for(&space).unwrap_err();
        assert!(
            error.contains("`rate_sensitivity`") && error.contains("missing"),
            "{error}"
        );
        let unknown =
            with("\"constants\":{\"yield_stress\":1.5e9,\"rate_sensitivity\":0.02,\"b\":1.0}");
        let error = unknown.values_for(&space).unwrap_err();
        assert!(error.contains("`b`"), "{error}");
        let old = with("\"values\":[1.5e9,0.02]");
        assert_eq!(old.values_for(&space).unwrap(), vec![1.5e9, 0.02]);
        let old_wrong = with("\"values\":[1.5e9,0.02,3.0]");
        assert!(old_wrong
            .values_for(&space)
            .unwrap_err()
            .contains("3 constants"));
    }

    #[test]
    fn sha256_matches_the_standard_vector() {
        // GOAL: the binary and campaign hashes are standard SHA-256.
        // SETUP: "abc". REFERENCE: FIPS 180-2 appendix B.1.
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }
}
