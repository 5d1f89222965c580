//! Result folders (`report/`, `diagnosis/`, a simulation's output) are written into a
//! temporary sibling and then put in place, so a reader never sees a half-written folder.
//!
//! The swap is two renames: the previous folder to `<name>.old-<pid>`, the new one from
//! `<name>.tmp-<pid>` to `<name>`; the old one is then removed. A process killed between the
//! two renames leaves `<name>.old-<pid>` and no `<name>`; a process killed while writing leaves
//! `<name>.tmp-<pid>`. The next run that holds the folder's run lock
//! ([`crate::run_lock::RunLock`]) puts such an old folder back and removes the leftovers
//! before it writes.

use std::path::{Path, PathBuf};

/// Whether leftovers of other processes may be cleaned: only under the folder's run lock.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Leftovers {
    /// Another process may be writing beside us: touch only this process's own temporary.
    Keep,
    /// This process holds the run lock: restore or remove every leftover sibling.
    Clean,
}

/// Write the folder `target` with `write` (given the temporary folder to fill) and put it in
/// place of any previous one.
pub(crate) fn write_folder(
    target: &Path,
    leftovers: Leftovers,
    write: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<(), String> {
    let sibling = |suffix: &str| -> PathBuf {
        let mut name = target.file_name().unwrap_or_default().to_os_string();
        name.push(suffix);
        target.with_file_name(name)
    };
    if leftovers == Leftovers::Clean {
        clean(target).map_err(|e| format!("{}: {e}", target.display()))?;
    }
    let pid = std::process::id();
    let temporary = sibling(&format!(".tmp-{pid}"));
    let old = sibling(&format!(".old-{pid}"));
    let _ = std::fs::remove_dir_all(&temporary);
    if let Err(message) = write(&temporary) {
        let _ = std::fs::remove_dir_all(&temporary);
        return Err(message);
    }
    let had_previous = target.exists();
    if had_previous {
        std::fs::rename(target, &old).map_err(|e| format!("{}: {e}", target.display()))?;
    }
    if let Err(e) = std::fs::rename(&temporary, target) {
        if had_previous {
            let _ = std::fs::rename(&old, target);
        }
        let _ = std::fs::remove_dir_all(&temporary);
        return Err(format!("{}: {e}", target.display()));
    }
    if had_previous {
        let _ = std::fs::remove_dir_all(&old);
    }
    Ok(())
}

/// Put back a previous folder a killed swap left as `<name>.old-*` (if `<name>` is missing)
/// and remove the other `<name>.tmp-*` and `<name>.old-*` siblings.
fn clean(target: &Path) -> std::io::Result<()> {
    let (Some(parent), Some(name)) = (target.parent(), target.file_name()) else {
        return Ok(());
    };
    let parent = if parent.as_os_str().is_empty() {
        Path::new(".")
    } else {
        parent
    };
    if !parent.exists() {
        return Ok(());
    }
    let name = name.to_string_lossy();
    let mut olds = Vec::new();
    let mut temporaries = Vec::new();
    for entry in std::fs::read_dir(parent)? {
        let entry = entry?;
        let file = entry.file_name().to_string_lossy().into_owned();
        if file.starts_with(&format!("{name}.old-")) {
            olds.push(entry.path());
        } else if file.starts_with(&format!("{name}.tmp-")) {
            temporaries.push(entry.path());
        }
    }
    olds.sort();
    if !target.exists() {
        if let Some(previous) = olds.pop() {
            std::fs::rename(previous, target)?;
        }
    }
    for path in olds.into_iter().chain(temporaries) {
        std::fs::remove_dir_all(path)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_killed_swap_is_repaired_and_leftovers_removed() {
        // GOAL: no half-written or missing result folder survives a killed run.
        // SETUP: a folder `report` swapped in twice; then the state a kill between the two
        //        renames leaves (`report.old-1`, no `report`) plus a stale `report.tmp-2`.
        // REFERENCE: each swap leaves exactly `report` with the new content; the next
        //        cleaning write first restores `report.old-1` (visible to its writer) and
        //        removes `report.tmp-2`; a failing write leaves the previous folder.
        let root = std::env::temp_dir().join(format!("stoss-swap-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        std::fs::create_dir_all(&root).unwrap();
        let target = root.join("report");
        let write_marker = |text: &'static str| {
            move |dir: &Path| -> Result<(), String> {
                std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
                std::fs::write(dir.join("marker"), text).map_err(|e| e.to_string())
            }
        };
        let marker = || std::fs::read_to_string(target.join("marker")).unwrap();
        let names = || -> Vec<String> {
            let mut names: Vec<String> = std::fs::read_dir(&root)
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect();
            names.sort();
            names
        };
        write_folder(&target, Leftovers::Clean, write_marker("one")).unwrap();
        write_folder(&target, Leftovers::Clean, write_marker("two")).unwrap();
        assert_eq!(marker(), "two");
        assert_eq!(names(), ["report"]);
        std::fs::rename(&target, root.join("report.old-1")).unwrap();
        std::fs::create_dir_all(root.join("report.tmp-2")).unwrap();
        write_folder(&target, Leftovers::Clean, |dir| {
            assert_eq!(
                marker(),
                "two",
                "the killed swap's folder is back before writing"
            );
            write_marker("three")(dir)
        })
        .unwrap();
        assert_eq!(marker(), "three");
        assert_eq!(names(), ["report"]);
        let failed = write_folder(&target, Leftovers::Clean, |_| Err("no".to_string()));
        assert!(failed.is_err());
        assert_eq!(marker(), "three");
        assert_eq!(names(), ["report"]);
        std::fs::remove_dir_all(&root).unwrap();
    }
}
