//! Clean interruption: the temporary files and folders a run is writing are removed when it is
//! stopped by SIGINT (Ctrl-C), SIGTERM or SIGHUP, and the process exits with 128 + the signal
//! (130, 143, 129); those a SIGKILL leaves carry the dead process's id in their name, and the
//! next run writing into the same folder removes them.
//!
//! Every temporary is created and registered, and renamed into place and unregistered, while
//! holding the registry's lock ([`atomically`]); the signal thread takes the same lock before
//! it removes what is registered, so a signal never finds a temporary that is not registered
//! yet, nor removes a finished output.

use std::collections::BTreeSet;
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The temporaries of this run, removed on a signal.
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The name prefix of crmorph's temporary output files: `.crmorph-<pid>-XXXXXX.tmp`.
pub(crate) fn file_prefix() -> String {
    format!(".crmorph-{}-", std::process::id())
}

/// The name prefix of crmorph's staging folders: `.crmorph-frames-<pid>-XXXXXX`.
pub(crate) fn folder_prefix() -> String {
    format!(".crmorph-frames-{}-", std::process::id())
}

/// Removes what is registered and exits with 128 + the signal on SIGINT, SIGTERM or SIGHUP,
/// from a thread of its own. Call once, early.
pub(crate) fn install() -> std::io::Result<()> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])?;
    std::thread::Builder::new()
        .name("crmorph-signals".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                let list = TEMPORARIES.lock().unwrap_or_else(|e| e.into_inner());
                for p in list.iter() {
                    remove(p);
                }
                std::process::exit(128 + signal);
            }
        })?;
    Ok(())
}

/// Runs `f` with the registry locked: create a temporary and register it in one step, or
/// rename it into place and unregister it in one step.
pub(crate) fn atomically<T>(f: impl FnOnce(&mut Vec<PathBuf>) -> T) -> T {
    let mut list = TEMPORARIES.lock().unwrap_or_else(|e| e.into_inner());
    f(&mut list)
}

/// A registered temporary, unregistered when dropped (declare it after the value that removes
/// the temporary on drop, so that the temporary is gone first).
#[derive(Debug)]
pub(crate) struct Registered(pub(crate) PathBuf);

impl Drop for Registered {
    fn drop(&mut self) {
        atomically(|list| list.retain(|p| p != &self.0));
    }
}

/// Removes a temporary file or folder (never following a symbolic link).
fn remove(p: &Path) {
    match std::fs::symlink_metadata(p) {
        Ok(m) if m.is_dir() => {
            let _ = std::fs::remove_dir_all(p);
        }
        Ok(_) => {
            let _ = std::fs::remove_file(p);
        }
        Err(_) => {}
    }
}

/// The process id in a name crmorph gives its temporaries (`.crmorph-<pid>-XXXXXX.tmp`, a
/// file; `.crmorph-frames-<pid>-XXXXXX`, a folder), with whether it names a folder.
fn owner_pid(name: &OsStr) -> Option<(u32, bool)> {
    let name = name.to_str()?;
    let (rest, folder) = match name.strip_prefix(".crmorph-frames-") {
        Some(rest) => (rest, true),
        None => (name.strip_prefix(".crmorph-")?.strip_suffix(".tmp")?, false),
    };
    let (pid, tail) = rest.split_once('-')?;
    if pid.is_empty() || !pid.bytes().all(|b| b.is_ascii_digit()) || tail.is_empty() {
        return None;
    }
    Some((pid.parse().ok()?, folder))
}

/// The folders [`clean_stale`] has listed in this run.
static CLEANED: Mutex<BTreeSet<PathBuf>> = Mutex::new(BTreeSet::new());

/// Removes the temporaries in `dir` that a crmorph process killed without a chance to clean
/// up left: names of crmorph's own pattern whose process is gone, a regular file or a folder
/// (never a symbolic link) owned by this user. Only where `/proc` tells which processes live
/// (Linux); errors are ignored. Once per folder and run: `crmorph batch` writes every output
/// of a folder through here, and listing the folder again for each would cost each pair time
/// in proportion to the outputs already written (issue 16).
pub(crate) fn clean_stale(dir: &Path) {
    let first = CLEANED
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(dir.to_path_buf());
    if !first {
        return;
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let proc = Path::new("/proc");
        let Ok(me) = std::fs::metadata("/proc/self") else {
            return;
        };
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let Some((pid, folder)) = owner_pid(&e.file_name()) else {
                continue;
            };
            if pid == std::process::id() || proc.join(pid.to_string()).exists() {
                continue;
            }
            let Ok(m) = std::fs::symlink_metadata(e.path()) else {
                continue;
            };
            let kind_ok = if folder { m.is_dir() } else { m.is_file() };
            if kind_ok && m.uid() == me.uid() {
                remove(&e.path());
            }
        }
    }
    #[cfg(not(unix))]
    let _ = dir;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_crmorphs_own_names_are_recognised() {
        let pid = |s: &str| owner_pid(OsStr::new(s));
        assert_eq!(pid(".crmorph-123-abcDEF.tmp"), Some((123, false)));
        assert_eq!(pid(".crmorph-frames-77-xYz123"), Some((77, true)));
        assert_eq!(
            pid(".crmorph-abcDEF.tmp"),
            None,
            "no pid: an older crmorph's"
        );
        assert_eq!(pid(".crmorph-123-.tmp"), None);
        assert_eq!(pid(".crmorph-12x-abc.tmp"), None);
        assert_eq!(pid(".crmorph-123-abc"), None);
        assert_eq!(pid("crmorph-123-abc.tmp"), None);
        assert_eq!(pid("frame_000.png"), None);
        assert!(file_prefix().starts_with(".crmorph-"));
    }

    #[test]
    fn stale_temporaries_of_dead_processes_are_removed() {
        let dir = tempfile::tempdir().unwrap();
        // A pid above the kernel's maximum (4,194,304) is never alive.
        let dead = dir.path().join(".crmorph-999999999-abcdef.tmp");
        let dead_dir = dir.path().join(".crmorph-frames-999999999-abcdef");
        let mine = dir.path().join(format!("{}abcdef.tmp", file_prefix()));
        let other = dir.path().join("keep.tmp");
        std::fs::write(&dead, b"x").unwrap();
        std::fs::create_dir(&dead_dir).unwrap();
        std::fs::write(dead_dir.join("frame_000.svg"), b"x").unwrap();
        std::fs::write(&mine, b"x").unwrap();
        std::fs::write(&other, b"x").unwrap();
        clean_stale(dir.path());
        assert!(!dead.exists() && !dead_dir.exists());
        assert!(mine.exists() && other.exists());
        // Listed once per run: what a killed process leaves later waits for the next run.
        std::fs::write(&dead, b"x").unwrap();
        clean_stale(dir.path());
        assert!(dead.exists());
    }
}
