//! Append-only JSON-lines journals: the resumable logs of `stoss calibrate`
//! (`simulations.jsonl`) and `stoss diagnose` (`diagnosis.jsonl`). Each entry is one line,
//! written and synced to disk as soon as it exists; a process killed mid-write leaves at most a
//! torn last line, which opening drops (and removes from the file, so the next entry starts on
//! a line of its own).

use serde::Serialize;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// An open journal.
pub struct Journal {
    path: PathBuf,
    file: std::fs::File,
}

impl Journal {
    /// Open (or create) `path`; returns the journal and its complete lines, in order.
    pub fn open(path: &Path) -> std::io::Result<(Self, Vec<String>)> {
        let mut lines = Vec::new();
        if path.exists() {
            let text = std::fs::read_to_string(path)?;
            let complete = text.rfind('\n').map_or(0, |i| i + 1);
            if complete < text.len() {
                std::fs::write(path, &text[..complete])?;
            }
            lines = text[..complete].lines().map(str::to_string).collect();
        }
        let file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)?;
        Ok((
            Self {
                path: path.into(),
                file,
            },
            lines,
        ))
    }

    /// Append `entry` as one line and sync it to disk.
    pub fn append<T: Serialize>(&mut self, entry: &T) -> std::io::Result<()> {
        let mut line = serde_json::to_string(entry).map_err(std::io::Error::other)?;
        line.push('\n');
        // One write of the whole line (the file is opened for appending), so lines of two
        // writers cannot interleave.
        self.file.write_all(line.as_bytes())?;
        self.file.sync_data()
    }

    /// The journal's path.
    pub fn path(&self) -> &Path {
        &self.path
    }
}
