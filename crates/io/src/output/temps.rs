//! The temporary files outputs are written to before they are renamed into place: how they
//! are named, the registry that lets an immediate quit (a second Ctrl-C) delete them, and the
//! removal of ones a killed run left behind.
//!
//! A temporary file is `.lumis-<pid>-<random>.tmp` in the target's directory. The pid says
//! which process owns it: a later run writing to the same directory deletes the ones whose
//! process is gone and that were last modified more than [`STALE_AFTER`] ago (the age guards
//! against a pid reused by an unrelated process that has just started). Files without a pid
//! (older lumis versions) are left alone.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Duration;

/// How old an orphaned temporary file must be before a later run deletes it.
pub const STALE_AFTER: Duration = Duration::from_secs(60);

const PREFIX: &str = ".lumis-";
const SUFFIX: &str = ".tmp";

/// Temporary files of this process that exist now (created, not yet renamed or deleted).
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Creates a temporary file `.lumis-<pid>-XXXXXX.tmp` in `dir` and registers it as live.
pub(super) fn create_in(dir: &Path) -> std::io::Result<tempfile::NamedTempFile> {
    let prefix = format!("{PREFIX}{}-", std::process::id());
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(SUFFIX);
    // NamedTempFile defaults to 0o600; ask for 0o666 so the umask gives the renamed file the
    // same permissions as any other file the user creates.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let temp = builder.tempfile_in(dir)?;
    register(temp.path());
    Ok(temp)
}

/// Records `path` as a live temporary file.
fn register(path: &Path) {
    live().push(path.to_path_buf());
}

/// Forgets `path` (it was renamed into place or deleted).
pub(super) fn unregister(path: &Path) {
    live().retain(|p| p != path);
}

fn live() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    // A panic while holding the lock leaves a valid list.
    LIVE.lock().unwrap_or_else(|e| e.into_inner())
}

/// Deletes every temporary file this process has not yet renamed into place. For paths that
/// end the process without running destructors (`std::process::exit` from the Ctrl-C handler).
pub fn remove_staged_temps() {
    for path in live().drain(..) {
        let _ = std::fs::remove_file(path);
    }
}

/// Deletes the orphaned temporary files in `dir` (see the module docs); returns how many.
/// Errors are ignored: cleaning up is a courtesy, never a reason to fail a run.
pub fn remove_stale_temps(dir: &Path) -> usize {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = name.to_str().and_then(owner_pid) else {
            continue;
        };
        if pid == std::process::id() || process_alive(pid) {
            continue;
        }
        let old_enough = entry
            .metadata()
            .ok()
            .filter(|m| m.is_file())
            .and_then(|m| m.modified().ok())
            .and_then(|t| t.elapsed().ok())
            .is_some_and(|age| age > STALE_AFTER);
        if old_enough && std::fs::remove_file(entry.path()).is_ok() {
            removed += 1;
        }
    }
    removed
}

/// The pid in a temporary file name `.lumis-<pid>-<random>.tmp`.
fn owner_pid(name: &str) -> Option<u32> {
    let rest = name.strip_prefix(PREFIX)?.strip_suffix(SUFFIX)?;
    let (pid, random) = rest.split_once('-')?;
    if random.is_empty() || !pid.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    pid.parse().ok()
}

/// Whether process `pid` exists. Linux: `/proc/<pid>`. Elsewhere there is no safe way to ask,
/// so every process counts as alive and nothing is deleted.
fn process_alive(pid: u32) -> bool {
    if cfg!(target_os = "linux") {
        Path::new("/proc").join(pid.to_string()).exists()
    } else {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn owner_pid_parses_only_our_names() {
        assert_eq!(owner_pid(".lumis-1234-abcDEF.tmp"), Some(1234));
        assert_eq!(owner_pid(".lumis-abcDEF.tmp"), None);
        assert_eq!(owner_pid(".lumis-12x-abc.tmp"), None);
        assert_eq!(owner_pid(".lumis-12-.tmp"), None);
        assert_eq!(owner_pid("lumis-12-abc.tmp"), None);
        assert_eq!(owner_pid(".lumis-12-abc.exr"), None);
    }

    #[test]
    fn builder_names_parse_back_to_this_process() {
        let dir = tempfile::tempdir().unwrap();
        let temp = create_in(dir.path()).unwrap();
        let name = temp
            .path()
            .file_name()
            .unwrap()
            .to_str()
            .unwrap()
            .to_string();
        assert_eq!(owner_pid(&name), Some(std::process::id()));
        unregister(temp.path());
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn removes_old_orphans_only() {
        let dir = tempfile::tempdir().unwrap();
        // pid_max on Linux is at most 2^22, so this pid cannot exist.
        let orphan = dir.path().join(".lumis-4294967-abc.tmp");
        let fresh_orphan = dir.path().join(".lumis-4294968-abc.tmp");
        let mine = dir
            .path()
            .join(format!(".lumis-{}-abc.tmp", std::process::id()));
        let other = dir.path().join("keep.tmp");
        for p in [&orphan, &fresh_orphan, &mine, &other] {
            std::fs::write(p, b"x").unwrap();
        }
        let old = std::time::SystemTime::now() - 2 * STALE_AFTER;
        for p in [&orphan, &mine, &other] {
            std::fs::File::options()
                .write(true)
                .open(p)
                .unwrap()
                .set_modified(old)
                .unwrap();
        }
        assert_eq!(remove_stale_temps(dir.path()), 1);
        assert!(!orphan.exists());
        assert!(fresh_orphan.exists() && mine.exists() && other.exists());
    }
}
