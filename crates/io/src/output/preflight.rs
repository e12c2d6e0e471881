//! The checks on a run's outputs made before any work starts, so that a long render cannot end
//! in an error it could have given at once, and so that no output destroys an input:
//!
//! - the output is a regular file, a symlink (chain) leading to one, or nothing yet (a new
//!   file, or a dangling symlink's end), never a FIFO, device, socket or directory, nor a link
//!   to one ([`target`](super::target) decides, again when the output is written);
//! - the directory of the file each output writes (for a symlink, the directory of the file it
//!   leads to) exists and a file can be created in it (a probe temporary file, deleted at
//!   once);
//! - no output is a file the run read ([`InputFile`]), and no two outputs are the same file.
//!   Files are compared by the canonical path of their directory plus their name (so `./x`,
//!   `x` and `dir/../x` agree) and, where the output already exists, by device and inode (so a
//!   hard link or a symlink to an input is caught too). A symlink is compared as the file it
//!   leads to.
//!
//! It also removes the stale temporary files of killed runs in those directories
//! ([`remove_stale_temps`](super::temps::remove_stale_temps)).

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use super::OutputError;
use super::staged::directory_of;
use super::{target, temps};
use crate::files::{InputFile, file_id};

/// One output of a run: the option that named it (`-o`, `--png`, `--out`) and its path.
#[derive(Clone, Copy, Debug)]
pub struct PlannedOutput<'a> {
    /// The option, for messages.
    pub flag: &'a str,
    /// The target path.
    pub path: &'a Path,
}

/// How a file is recognised: canonical directory plus name, and (dev, inode) if it exists.
struct Identity {
    path: PathBuf,
    id: Option<(u64, u64)>,
}

impl Identity {
    fn same_as(&self, other_path: &Path, other_id: Option<(u64, u64)>) -> bool {
        self.path == other_path || (self.id.is_some() && self.id == other_id)
    }
}

/// Checks `outputs` against each other and against `inputs` (module docs) and cleans stale
/// temporary files in their directories. Nothing is written; the first problem is returned.
pub fn prepare_outputs(
    outputs: &[PlannedOutput<'_>],
    inputs: &[InputFile],
) -> Result<(), OutputError> {
    let mut seen: Vec<(PlannedOutput<'_>, Identity)> = Vec::new();
    let mut probed: HashSet<PathBuf> = HashSet::new();
    for out in outputs {
        let identity = identify(out)?;
        if let Some(input) = inputs.iter().find(|i| identity.same_as(&i.canonical, i.id)) {
            return Err(OutputError::IsInput {
                flag: out.flag.to_string(),
                path: out.path.to_path_buf(),
                input: input.path.clone(),
            });
        }
        if let Some((other, _)) = seen.iter().find(|(_, o)| identity.same_as(&o.path, o.id)) {
            return Err(OutputError::SameFile {
                flag: out.flag.to_string(),
                path: out.path.to_path_buf(),
                other_flag: other.flag.to_string(),
                other: other.path.to_path_buf(),
            });
        }
        let dir = identity
            .path
            .parent()
            .unwrap_or(Path::new("/"))
            .to_path_buf();
        if probed.insert(dir.clone()) {
            probe_writable(out, &dir)?;
            temps::remove_stale_temps(&dir);
        }
        seen.push((*out, identity));
    }
    Ok(())
}

/// The identity of the file `out` writes, checking that it is a regular file or none (module
/// docs) and that its directory exists.
fn identify(out: &PlannedOutput<'_>) -> Result<Identity, OutputError> {
    let no_dir = |resolved: Option<&Path>, dir: &Path| OutputError::NoDirectory {
        flag: out.flag.to_string(),
        path: out.path.to_path_buf(),
        resolved: resolved.map(Path::to_path_buf),
        dir: dir.to_path_buf(),
    };
    let is_dir = || OutputError::IsDirectory {
        flag: out.flag.to_string(),
        path: out.path.to_path_buf(),
    };
    // The directory the user typed first: a typo there is the likeliest problem.
    if !directory_of(out.path).is_dir() {
        return Err(no_dir(None, directory_of(out.path)));
    }
    // `x/..` or `/` names a directory, never a file to write.
    out.path.file_name().ok_or_else(is_dir)?;
    let target = target::resolve(out.path, Some(out.flag))?;
    let resolved = target.linked.then_some(target.file.as_path());
    let dir = directory_of(&target.file);
    // A dangling symlink creates the file it names, so that file's directory must exist.
    if !dir.is_dir() {
        return Err(no_dir(resolved, dir));
    }
    let name = target.file.file_name().ok_or_else(is_dir)?;
    let canonical_dir = std::fs::canonicalize(dir).map_err(|_| no_dir(resolved, dir))?;
    let meta = std::fs::metadata(&target.file).ok();
    Ok(Identity {
        path: canonical_dir.join(name),
        id: meta.as_ref().and_then(file_id),
    })
}

/// Creates and deletes a temporary file in `dir`: the only reliable test that the final write
/// can create its temporary file there (permissions, ACLs, read-only mounts, quotas).
fn probe_writable(out: &PlannedOutput<'_>, dir: &Path) -> Result<(), OutputError> {
    let probe = temps::create_in(dir).map_err(|source| OutputError::NotWritable {
        flag: out.flag.to_string(),
        path: out.path.to_path_buf(),
        dir: dir.to_path_buf(),
        source,
    })?;
    temps::unregister(probe.path());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::files::{read_regular, record_inputs};

    fn out<'a>(flag: &'a str, path: &'a Path) -> PlannedOutput<'a> {
        PlannedOutput { flag, path }
    }

    #[test]
    fn refuses_an_input_however_spelt() {
        let dir = tempfile::tempdir().unwrap();
        let scene = dir.path().join("s.toml");
        std::fs::write(&scene, b"x").unwrap();
        let ((), inputs) = record_inputs(|| {
            read_regular(&scene).unwrap();
        });
        let dotted = dir.path().join(".").join("sub/../s.toml");
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        let link = dir.path().join("hard.toml");
        std::fs::hard_link(&scene, &link).unwrap();
        for p in [&scene, &dotted, &link] {
            let err = prepare_outputs(&[out("--out", p)], &inputs).unwrap_err();
            assert!(matches!(err, OutputError::IsInput { .. }), "{p:?}: {err}");
        }
        let other = dir.path().join("other.npy");
        prepare_outputs(&[out("--out", &other)], &inputs).unwrap();
    }

    #[test]
    fn refuses_two_outputs_that_are_one_file() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.exr");
        let again = dir.path().join("./a.exr");
        let err = prepare_outputs(&[out("-o", &a), out("--png", &again)], &[]).unwrap_err();
        assert!(matches!(err, OutputError::SameFile { .. }), "{err}");
    }

    #[test]
    fn refuses_missing_directories_and_directories() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("none/a.png");
        let err = prepare_outputs(&[out("--png", &missing)], &[]).unwrap_err();
        assert!(matches!(err, OutputError::NoDirectory { .. }), "{err}");
        let err = prepare_outputs(&[out("-o", dir.path())], &[]).unwrap_err();
        assert!(matches!(err, OutputError::NotRegular { .. }), "{err}");
        let err = prepare_outputs(&[out("-o", &dir.path().join(".."))], &[]).unwrap_err();
        assert!(matches!(err, OutputError::IsDirectory { .. }), "{err}");
        // Nothing was left behind by the probes.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}
