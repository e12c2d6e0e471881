//! Write-to-temporary-then-rename, for one output or for all outputs of a run together.
//!
//! Every output is first encoded into a temporary file in its target's directory ([`temps`]:
//! the same directory, because `rename` is only atomic within one file system), flushed and
//! synced. Only when every output of the run has been written are the temporary files renamed
//! onto their targets, in the order they were staged. So a failure while encoding or writing
//! any of them (a full disk, a missing directory) leaves every existing file unchanged and no
//! temporary file behind.
//!
//! What this cannot promise: the renames of several files are not one atomic step. A crash or
//! a failed rename between two renames leaves the earlier targets new and the later ones old;
//! each file on its own is always either the complete old or the complete new one, never torn.
//!
//! [`temps`]: super::temps

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use tempfile::TempPath;

use super::OutputError;
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
    target: PathBuf,
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

    /// Runs `encode` against a new temporary file beside `path`, then flushes and syncs it.
    /// On any error the temporary file is deleted; `path` is not touched either way until
    /// [`commit`](Self::commit).
    pub fn stage<F>(&mut self, path: &Path, encode: F) -> Result<(), OutputError>
    where
        F: FnOnce(&mut TempWriter<'_>) -> Result<(), OutputError>,
    {
        let mut temp =
            temps::create_in(directory_of(path)).map_err(|source| OutputError::CreateTemp {
                path: path.to_path_buf(),
                source,
            })?;
        if let Err(e) = fill(temp.as_file_mut(), path, encode) {
            temps::unregister(temp.path());
            return Err(e);
        }
        self.staged.push(Staged {
            target: path.to_path_buf(),
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

    /// Renames every temporary file onto its target, in the order staged. If a rename fails,
    /// the targets before it are already replaced (see the module docs), the rest are left
    /// unchanged and their temporary files deleted.
    pub fn commit(mut self) -> Result<(), OutputError> {
        for s in &mut self.staged {
            let Some(temp) = s.temp.take() else { continue };
            let temp_name = temp.to_path_buf();
            match temp.persist(&s.target) {
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
/// `path` is replaced, not written through.
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
