//! The on-disk cache of blast loads. A load is one-way coupled (it does not depend on the
//! plate's constants), so it is computed once per charge, stand-off, air and grid and reused
//! by every simulation of a calibration. Entries are keyed by the canonical JSON of their
//! inputs and the solver version (`near-field-<FNV-1a 64 of the key>.json`); the key is
//! stored in the entry and compared on reading, so a hash collision recomputes instead of
//! returning another charge's load. Writes go to a temporary file renamed into place, so a
//! process that dies leaves no partial entry. A process-wide map keeps loaded entries.

use crate::hash::fnv1a;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};

use serde::{Deserialize, Serialize};

use super::near_field::{BlastError, BlastRun, NearFieldBlast};
use crate::solver::PressureHistory;

/// Bumped whenever the Euler solver's results change, so stale entries are not reused.
pub const SOLVER_VERSION: u32 = 2;

/// Where a load came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// Computed by this call (and stored).
    Computed,
    /// Read from the cache folder.
    Disk,
    /// Already in this process's memory (from the same folder).
    Memory,
}

/// A cached load.
#[derive(Clone, Debug)]
pub struct CachedLoad {
    /// The wall overpressure.
    pub wall: Arc<PressureHistory>,
    /// Where it came from.
    pub source: Source,
    /// The Euler run's statistics when computed now.
    pub run: Option<BlastRun>,
    /// The entry's file.
    pub path: PathBuf,
}

/// Why the cache failed.
#[derive(Debug, thiserror::Error)]
pub enum CacheError {
    /// The load could not be computed.
    #[error(transparent)]
    Blast(BlastError),
    /// The cache folder or an entry could not be read or written.
    #[error("blast-load cache {path}: {message}")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What failed.
        message: String,
    },
}

#[derive(Serialize, Deserialize)]
struct Entry {
    key: String,
    wall: PressureHistory,
}

fn memory() -> &'static Mutex<HashMap<String, Arc<PressureHistory>>> {
    static MEMORY: OnceLock<Mutex<HashMap<String, Arc<PressureHistory>>>> = OnceLock::new();
    MEMORY.get_or_init(|| Mutex::new(HashMap::new()))
}

/// The canonical key of a load.
pub fn key(blast: &NearFieldBlast, plate_radius: f64) -> String {
    let inputs = serde_json::json!({
        "solver_version": SOLVER_VERSION,
        "blast": blast,
        "plate_radius": plate_radius,
    });
    inputs.to_string()
}

/// The default cache folder: `$STOSS_CACHE_DIR`, else `$XDG_CACHE_HOME/stoss`, else
/// `$HOME/.cache/stoss`, else `.stoss-cache` in the working folder.
pub fn default_folder() -> PathBuf {
    if let Some(dir) = std::env::var_os("STOSS_CACHE_DIR") {
        return PathBuf::from(dir);
    }
    if let Some(dir) = std::env::var_os("XDG_CACHE_HOME") {
        return PathBuf::from(dir).join("stoss");
    }
    if let Some(home) = std::env::var_os("HOME") {
        return PathBuf::from(home).join(".cache").join("stoss");
    }
    PathBuf::from(".stoss-cache")
}

fn io(path: &Path, error: impl std::fmt::Display) -> CacheError {
    CacheError::Io {
        path: path.to_path_buf(),
        message: error.to_string(),
    }
}

/// The wall load of `blast` over a plate of radius `plate_radius`: from memory, from
/// `folder`, or computed and stored there. `progress(time)` follows a computation.
pub fn load(
    blast: &NearFieldBlast,
    plate_radius: f64,
    folder: &Path,
    progress: &mut dyn FnMut(f64),
) -> Result<CachedLoad, CacheError> {
    blast.validate(plate_radius).map_err(CacheError::Blast)?;
    let key = key(blast, plate_radius);
    let path = folder.join(format!("near-field-{:016x}.json", fnv1a(&key)));
    // The memory layer mirrors the folder's entries, so it is keyed by the entry's path too.
    let memory_key = format!("{}\n{key}", path.display());
    if let Some(wall) = memory().lock().map_err(|e| io(&path, e))?.get(&memory_key) {
        return Ok(CachedLoad {
            wall: wall.clone(),
            source: Source::Memory,
            run: None,
            path,
        });
    }
    if let Ok(text) = std::fs::read_to_string(&path) {
        if let Ok(entry) = serde_json::from_str::<Entry>(&text) {
            if entry.key == key {
                let wall = Arc::new(entry.wall);
                memory()
                    .lock()
                    .map_err(|e| io(&path, e))?
                    .insert(memory_key, wall.clone());
                return Ok(CachedLoad {
                    wall,
                    source: Source::Disk,
                    run: None,
                    path,
                });
            }
        }
    }
    // Check that the folder can take the entry before spending the computation.
    std::fs::create_dir_all(folder).map_err(|e| io(folder, e))?;
    let probe = folder.join(format!(".probe-{}", std::process::id()));
    std::fs::write(&probe, b"").map_err(|e| io(folder, e))?;
    let _ = std::fs::remove_file(&probe);
    let run = blast
        .solve(plate_radius, progress)
        .map_err(CacheError::Blast)?;
    let entry = Entry {
        key: key.clone(),
        wall: run.wall.clone(),
    };
    let text = serde_json::to_string(&entry).map_err(|e| io(&path, e))?;
    let temporary = folder.join(format!(
        ".near-field-{:016x}.{}.tmp",
        fnv1a(&key),
        std::process::id()
    ));
    std::fs::write(&temporary, text).map_err(|e| io(&temporary, e))?;
    std::fs::rename(&temporary, &path).map_err(|e| io(&path, e))?;
    let wall = Arc::new(run.wall.clone());
    memory()
        .lock()
        .map_err(|e| io(&path, e))?
        .insert(memory_key, wall.clone());
    Ok(CachedLoad {
        wall,
        source: Source::Computed,
        run: Some(run),
        path,
    })
}

/// Forget the loads kept in this process's memory (the next [`load`] reads the disk).
pub fn forget_memory() {
    if let Ok(mut map) = memory().lock() {
        map.clear();
    }
}
