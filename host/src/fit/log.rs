//! The simulation log (`simulations.jsonl`, a [`Journal`]): one JSON line per simulated
//! candidate, appended and synced to disk as soon as its simulations end. A killed run is resumed by replaying the
//! (deterministic, seeded) optimisation: every proposal found in the log under the same key
//! and with bit-identical constants is taken from the log instead of being simulated again.

use super::executor::Origin;
use super::fidelity::Fidelity;
use super::objective::Evaluation;
use crate::journal::Journal;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Where a candidate belongs: model, fold (`None` = fit on every fitted experiment; `Some(name)`
/// = leave-one-out fold without that experiment), instance and position in its sequence.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Key {
    /// Model name.
    pub model: String,
    /// Leave-one-out fold (the left-out experiment's file), or `None`.
    pub fold: Option<String>,
    /// Instance number.
    pub instance: usize,
    /// Index of the candidate in its instance's sequence.
    pub index: usize,
    /// The mesh it was simulated on (multi-fidelity: a coarse candidate and its fine check
    /// share the rest of the key); absent for the fine one, as in logs written before.
    #[serde(default, skip_serializing_if = "Fidelity::is_fine")]
    pub fidelity: Fidelity,
}

/// One log line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Entry {
    /// Where the candidate belongs.
    pub key: Key,
    /// The optimiser seed of its instance.
    pub seed: u64,
    /// The evaluation.
    pub evaluation: Evaluation,
    /// Where and by which stoss binary it was computed (absent in logs written before
    /// stoss recorded it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub origin: Option<Origin>,
}

/// Why the log could not be used.
#[derive(Debug, thiserror::Error)]
pub enum LogError {
    /// Reading or writing failed.
    #[error("{0}: {1}")]
    Io(PathBuf, #[source] std::io::Error),
    /// A line is not a valid entry.
    #[error("{0}:{1}: {2}")]
    Corrupt(PathBuf, usize, String),
    /// An entry exists under the same key with other constants: the campaign changed.
    #[error(
        "{0}: the logged candidate {1:?} differs from this run's: the campaign or stoss changed since the log was written; start a new output folder"
    )]
    Mismatch(PathBuf, Key),
}

/// An open simulation log.
pub struct SimulationLog {
    path: PathBuf,
    entries: HashMap<Key, Entry>,
    journal: Journal,
    /// Entries reused from the log in this run.
    pub reused: usize,
}

impl SimulationLog {
    /// Open `path`: read existing entries (a torn last line from a killed run is dropped) and
    /// append from there.
    pub fn open(path: &Path) -> Result<Self, LogError> {
        let (journal, lines) = Journal::open(path).map_err(|e| LogError::Io(path.into(), e))?;
        let mut entries = HashMap::new();
        for (index, line) in lines.iter().enumerate() {
            let entry: Entry = serde_json::from_str(line)
                .map_err(|e| LogError::Corrupt(path.into(), index + 1, e.to_string()))?;
            entries.insert(entry.key.clone(), entry);
        }
        Ok(Self {
            path: path.into(),
            entries,
            journal,
            reused: 0,
        })
    }

    /// Entries read or written so far.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// `true` if the log is empty.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The logged evaluation of `key`, if its constants are bit-identical to `values`.
    pub fn lookup(&mut self, key: &Key, values: &[f64]) -> Result<Option<Evaluation>, LogError> {
        match self.entries.get(key) {
            None => Ok(None),
            Some(entry) => {
                let same = entry.evaluation.values.len() == values.len()
                    && entry
                        .evaluation
                        .values
                        .iter()
                        .zip(values)
                        .all(|(a, b)| a.to_bits() == b.to_bits());
                if same {
                    self.reused += 1;
                    Ok(Some(entry.evaluation.clone()))
                } else {
                    Err(LogError::Mismatch(self.path.clone(), key.clone()))
                }
            }
        }
    }

    /// Append an entry and sync it to disk.
    pub fn append(&mut self, entry: Entry) -> Result<(), LogError> {
        self.journal
            .append(&entry)
            .map_err(|e| LogError::Io(self.path.clone(), e))?;
        self.entries.insert(entry.key.clone(), entry);
        Ok(())
    }

    /// Every entry (unordered).
    pub fn entries(&self) -> impl Iterator<Item = &Entry> {
        self.entries.values()
    }
}
