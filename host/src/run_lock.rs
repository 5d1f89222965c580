//! One run per output folder: `stoss calibrate` and `stoss diagnose` hold an advisory lock on
//! `<folder>/.stoss-run.lock` for as long as they run. A second run on the same folder is
//! refused with a message; the operating system releases the lock when the holder exits or is
//! killed (even with `kill -9`), so a lock left by a dead run is taken over by the next one.
//! A run that ends (cleanly or with an error) removes the lock file; only a killed run leaves
//! one behind.

use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read as _, Seek as _, Write as _};
use std::path::{Path, PathBuf};

/// Name of the lock file inside an output folder.
pub const LOCK_FILE: &str = ".stoss-run.lock";

/// A held run lock; dropping it releases the folder.
#[derive(Debug)]
pub struct RunLock {
    _file: File,
    path: PathBuf,
}

impl RunLock {
    /// Lock `folder` (which must exist) for this process, recording its id in the lock file;
    /// an error names the folder and the process holding it.
    pub fn acquire(folder: &Path) -> Result<Self, String> {
        let path = folder.join(LOCK_FILE);
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        match file.try_lock() {
            Ok(()) if !same_file(&file, &path) => {
                // The holder removed the file between our open and our lock: the lock is on
                // a file no other run will find. Take the folder's current file instead.
                drop(file);
                return Self::acquire(folder);
            }
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => {
                let mut holder = String::new();
                let _ = file.read_to_string(&mut holder);
                let holder = holder.trim();
                return Err(format!(
                    "{}: another stoss run is using this folder ({}); wait for it to finish or \
                     choose another --output",
                    folder.display(),
                    if holder.is_empty() {
                        "its lock is held".to_string()
                    } else {
                        format!("process {holder}")
                    }
                ));
            }
            Err(TryLockError::Error(e)) => return Err(format!("{}: {e}", path.display())),
        }
        let record = format!("{}\n", std::process::id());
        file.set_len(0)
            .and_then(|()| file.rewind())
            .and_then(|()| file.write_all(record.as_bytes()))
            .map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(Self { _file: file, path })
    }

    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for RunLock {
    /// Remove the lock file while the lock is still held (a run waiting on it then finds the
    /// file gone and takes the folder's new one, [`same_file`]).
    fn drop(&mut self) {
        if same_file(&self._file, &self.path) {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// Whether the open `file` is the file at `path` (the same device and inode); `false` if
/// `path` is gone.
#[cfg(unix)]
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt as _;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(open), Ok(named)) => open.dev() == named.dev() && open.ino() == named.ino(),
        _ => false,
    }
}

/// Whether the open `file` is the file at `path` (without inodes: the path exists).
#[cfg(not(unix))]
fn same_file(_file: &File, path: &Path) -> bool {
    path.exists()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_lock_on_a_folder_is_refused_until_the_first_is_dropped() {
        // GOAL: one holder per folder; the lock is released on drop.
        // SETUP: a temporary folder locked twice from this process (two open file
        //        descriptions, so the advisory lock conflicts as between processes).
        // REFERENCE: the second acquire fails naming the folder and this process; after the
        //        first is dropped, its file is gone (a handle opened on it before no longer
        //        names the folder's lock) and acquiring succeeds.
        let folder = std::env::temp_dir().join(format!("stoss-lock-{}", std::process::id()));
        std::fs::create_dir_all(&folder).unwrap();
        let first = RunLock::acquire(&folder).unwrap();
        let error = RunLock::acquire(&folder).unwrap_err();
        assert!(error.contains("another stoss run"), "{error}");
        assert!(
            error.contains(&format!("process {}", std::process::id())),
            "{error}"
        );
        assert!(first.path().ends_with(LOCK_FILE));
        // A run that waited on the first lock's file keeps its handle after the holder ends.
        let stale = OpenOptions::new()
            .read(true)
            .write(true)
            .open(first.path())
            .unwrap();
        drop(first);
        assert!(
            !folder.join(LOCK_FILE).exists(),
            "the lock file is removed when the run ends"
        );
        assert!(!same_file(&stale, &folder.join(LOCK_FILE)));
        let again = RunLock::acquire(&folder).unwrap();
        assert!(folder.join(LOCK_FILE).exists());
        drop(again);
        assert!(!folder.join(LOCK_FILE).exists());
        std::fs::remove_dir_all(&folder).unwrap();
    }
}
