//! Write-to-temporary-then-rename, for one output or for all outputs of a run together.
//!
//! Every output is first encoded into a temporary file in its target's directory ([`temps`]:
//! the same directory, because `rename` is only atomic within one file system), flushed and
//! synced. Only when every output of the run has been written are the temporary files renamed
//! onto their targets, in the order they were staged. So a failure while encoding or writing
//! any of them (a full disk, a missing directory) leaves every existing file unchanged and no
//! temporary file behind.
//!
//! The file replaced is the one the target path leads to ([`target`]): a symlink to a regular
//! file is written through, and a target that is (or leads to) a FIFO, a device, a socket or a
//! directory is refused, both when it is staged and again, for every output, before the first
//! rename, so a target that changed during the run stops the whole commit.
//!
//! What this cannot promise: the renames of several files are not one atomic step. A crash or
//! a failed rename between two renames leaves the earlier targets new and the later ones old;
//! each file on its own is always either the complete old or the complete new one, never torn.
//!
//! A target swapped for a FIFO between that last check and its rename is still replaced.
//!
//! [`temps`]: super::temps
//! [`target`]: super::target

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use tempfile::TempPath;

use super::OutputError;
use super::target::{self, Target};
use super::temps;

/// The writer an encoder gets: a buffered temporary file.
pub type TempWriter<'a> = BufWriter<&'a mut File>;

/// Outputs written to temporary files and not yet renamed into place. Dropping it without
/// [`commit`](Self::commit) deletes the temporary files and leaves every target as it was.
#[derive(Default)]
pub struct StagedOutputs {
    staged: Vec<Staged>,
}

/// One finished temporary file and where it goes.
struct Staged {
    /// The path as given, for messages.
    target: PathBuf,
    /// The file the rename replaces: `target` or where its symlinks led when staged.
    file: PathBuf,
    /// `None` once renamed.
    temp: Option<TempPath>,
}

impl Drop for Staged {
    fn drop(&mut self) {
        if let Some(temp) = self.temp.take() {
            temps::unregister(&temp);
            // Dropping a TempPath deletes the file.
        }
    }
}

impl StagedOutputs {
    /// Nothing staged yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Runs `encode` against a new temporary file beside the file `path` leads to (itself, or
    /// the end of its symlinks), then flushes and syncs it. On any error the temporary file is
    /// deleted; `path` is not touched either way until [`commit`](Self::commit). A `path` that
    /// is not a regular file, or leads to none, is refused before anything is created.
    pub fn stage<F>(&mut self, path: &Path, encode: F) -> Result<(), OutputError>
    where
        F: FnOnce(&mut TempWriter<'_>) -> Result<(), OutputError>,
    {
        let Target { file, .. } = target::resolve(path, None)?;
        let mut temp =
            temps::create_in(directory_of(&file)).map_err(|source| OutputError::CreateTemp {
                path: path.to_path_buf(),
                source,
            })?;
        if let Err(e) = fill(temp.as_file_mut(), path, encode) {
            temps::unregister(temp.path());
            return Err(e);
        }
        self.staged.push(Staged {
            target: path.to_path_buf(),
            file,
            temp: Some(temp.into_temp_path()),
        });
        Ok(())
    }

    /// [`stage`](Self::stage) of a finished byte string.
    pub fn stage_bytes(&mut self, path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
        use std::io::Write as _;
        self.stage(path, |w| {
            w.write_all(bytes).map_err(|source| OutputError::Write {
                path: path.to_path_buf(),
                source,
            })
        })
    }

    /// The targets staged so far, in order.
    pub fn targets(&self) -> impl Iterator<Item = &Path> {
        self.staged.iter().map(|s| s.target.as_path())
    }

    /// Renames every temporary file onto its target, in the order staged. Every target is
    /// first checked again (module docs): if one is no longer a regular file or leads to
    /// another file than when it was staged, nothing is renamed. If a rename fails, the
    /// targets before it are already replaced (see the module docs), the rest are left
    /// unchanged and their temporary files deleted.
    pub fn commit(mut self) -> Result<(), OutputError> {
        for s in self.staged.iter().filter(|s| s.temp.is_some()) {
            let now = target::resolve(&s.target, None)?;
            if now.file != s.file {
                return Err(OutputError::TargetChanged {
                    path: s.target.clone(),
                    was: s.file.clone(),
                    now: now.file,
                });
            }
        }
        for s in &mut self.staged {
            let Some(temp) = s.temp.take() else { continue };
            let temp_name = temp.to_path_buf();
            match temp.persist(&s.file) {
                Ok(()) => temps::unregister(&temp_name),
                Err(e) => {
                    // Put it back so that dropping `self` deletes it.
                    s.temp = Some(e.path);
                    return Err(OutputError::Persist {
                        path: s.target.clone(),
                        source: e.error,
                    });
                }
            }
        }
        Ok(())
    }
}

/// Encodes into `file`, then flushes and syncs it.
fn fill<F>(file: &mut File, path: &Path, encode: F) -> Result<(), OutputError>
where
    F: FnOnce(&mut TempWriter<'_>) -> Result<(), OutputError>,
{
    let write_err = |source| OutputError::Write {
        path: path.to_path_buf(),
        source,
    };
    {
        let mut writer = BufWriter::new(&mut *file);
        encode(&mut writer)?;
        writer.into_inner().map_err(|e| write_err(e.into_error()))?;
    }
    // Sync before the rename so a crash cannot leave a renamed but empty file.
    file.sync_all().map_err(write_err)
}

/// The directory a target's temporary file goes in: its parent, `.` for a bare file name.
pub fn directory_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Writes one output on its own: [`StagedOutputs::stage`] then [`StagedOutputs::commit`]. The
/// target is either the old file or the complete new one, never a truncated mix. A symlink at
/// `path` is written through: the file it leads to is replaced, the link stays.
pub fn write_atomically<F>(path: &Path, encode: F) -> Result<(), OutputError>
where
    F: FnOnce(&mut TempWriter<'_>) -> Result<(), OutputError>,
{
    let mut staged = StagedOutputs::new();
    staged.stage(path, encode)?;
    staged.commit()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    fn unsupported(path: &Path) -> OutputError {
        OutputError::UnsupportedExtension {
            path: path.to_path_buf(),
        }
    }

    #[test]
    fn failing_encoder_keeps_old_file_and_removes_temp() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("out.png");
        std::fs::write(&target, b"old image").unwrap();

        let result = write_atomically(&target, |w| {
            // Half-written data must never reach the target.
            w.write_all(b"partial").unwrap();
            w.flush().unwrap();
            Err(unsupported(&target))
        });

        assert!(result.is_err());
        assert_eq!(std::fs::read(&target).unwrap(), b"old image");
        assert_eq!(entries(dir.path()), ["out.png"]);
    }

    #[test]
    fn success_replaces_target_and_removes_temp() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("out.png");
        std::fs::write(&target, b"old image").unwrap();

        write_atomically(&target, |w| {
            w.write_all(b"new image")
                .map_err(|source| OutputError::Write {
                    path: target.clone(),
                    source,
                })
        })
        .unwrap();

        assert_eq!(std::fs::read(&target).unwrap(), b"new image");
        assert_eq!(entries(dir.path()), ["out.png"]);
    }

    #[test]
    fn a_later_failure_keeps_every_earlier_target() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a.exr"), dir.path().join("b.png"));
        std::fs::write(&a, b"old a").unwrap();
        let mut staged = StagedOutputs::new();
        staged.stage_bytes(&a, b"new a").unwrap();
        assert!(staged.stage(&b, |_| Err(unsupported(&b))).is_err());
        assert!(
            staged
                .stage_bytes(&dir.path().join("none/c.png"), b"c")
                .is_err()
        );
        drop(staged);
        assert_eq!(std::fs::read(&a).unwrap(), b"old a");
        assert_eq!(entries(dir.path()), ["a.exr"]);
    }

    #[cfg(unix)]
    #[test]
    fn writes_through_symlinks_into_the_linked_directory() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::create_dir(d.join("real")).unwrap();
        std::fs::write(d.join("real/a.exr"), b"old a").unwrap();
        std::os::unix::fs::symlink("real/a.exr", d.join("link.exr")).unwrap();
        std::os::unix::fs::symlink("real/b.png", d.join("dangling.png")).unwrap();
        let mut staged = StagedOutputs::new();
        staged.stage_bytes(&d.join("link.exr"), b"new a").unwrap();
        staged
            .stage_bytes(&d.join("dangling.png"), b"new b")
            .unwrap();
        // The temporary files sit beside the files they replace, not beside the links.
        assert_eq!(
            entries(&d.join("real")).len(),
            3,
            "{:?}",
            entries(&d.join("real"))
        );
        staged.commit().unwrap();
        assert_eq!(std::fs::read(d.join("real/a.exr")).unwrap(), b"new a");
        assert_eq!(std::fs::read(d.join("real/b.png")).unwrap(), b"new b");
        assert!(d.join("link.exr").symlink_metadata().unwrap().is_symlink());
        assert_eq!(entries(&d.join("real")), ["a.exr", "b.png"]);
    }

    #[cfg(unix)]
    #[test]
    fn a_target_changed_before_the_commit_stops_every_rename() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let (a, b) = (d.join("a.exr"), d.join("b.png"));
        std::fs::write(&a, b"old a").unwrap();
        std::fs::write(d.join("x.png"), b"x").unwrap();
        std::fs::write(d.join("y.png"), b"y").unwrap();
        for change in ["directory", "relink"] {
            std::os::unix::fs::symlink("x.png", &b).unwrap();
            let mut staged = StagedOutputs::new();
            staged.stage_bytes(&a, b"new a").unwrap();
            staged.stage_bytes(&b, b"new b").unwrap();
            std::fs::remove_file(&b).unwrap();
            if change == "directory" {
                std::fs::create_dir(&b).unwrap();
            } else {
                std::os::unix::fs::symlink("y.png", &b).unwrap();
            }
            let err = staged.commit().unwrap_err();
            let expected = match change {
                "directory" => matches!(err, OutputError::NotRegular { .. }),
                _ => matches!(err, OutputError::TargetChanged { .. }),
            };
            assert!(expected, "{change}: {err}");
            assert_eq!(std::fs::read(&a).unwrap(), b"old a", "{change}");
            assert_eq!(std::fs::read(d.join("x.png")).unwrap(), b"x");
            assert_eq!(std::fs::read(d.join("y.png")).unwrap(), b"y");
            assert_eq!(entries(d), ["a.exr", "b.png", "x.png", "y.png"], "{change}");
            if change == "directory" {
                std::fs::remove_dir(&b).unwrap();
            } else {
                std::fs::remove_file(&b).unwrap();
            }
        }
    }

    #[test]
    fn commit_renames_all() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a.exr"), dir.path().join("b.png"));
        std::fs::write(&a, b"old a").unwrap();
        let mut staged = StagedOutputs::new();
        staged.stage_bytes(&a, b"new a").unwrap();
        staged.stage_bytes(&b, b"new b").unwrap();
        assert_eq!(entries(dir.path()).len(), 3, "a.exr and two temporaries");
        staged.commit().unwrap();
        assert_eq!(std::fs::read(&a).unwrap(), b"new a");
        assert_eq!(std::fs::read(&b).unwrap(), b"new b");
        assert_eq!(entries(dir.path()), ["a.exr", "b.png"]);
    }
}
