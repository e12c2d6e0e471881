//! Which file an output path really writes, decided the same way before the work
//! ([`prepare_outputs`](super::prepare_outputs)), when the output is staged and again just
//! before it is renamed into place ([`StagedOutputs`](super::StagedOutputs)):
//!
//! - nothing there: the file is created;
//! - a regular file: it is replaced;
//! - a symlink, or a chain of them, ending at a regular file: that file is replaced and the
//!   links stay links. The temporary file goes in the *resolved* file's directory, so the
//!   rename is atomic there (a rename onto the link would replace the link instead);
//! - a dangling symlink: the file it names is created, as a shell's `>` would, if that file's
//!   directory exists (the preflight says which directory is missing otherwise);
//! - a FIFO, a character or block device, a socket or a directory, or a symlink leading to
//!   one: refused, naming what it is. The target is only `lstat`ed, never opened (an open for
//!   writing blocks on a FIFO), and never renamed over: that would silently swap the FIFO or
//!   `/dev/null` for a regular file, which is not what a user naming one asked for;
//! - a symlink loop (more than [`MAX_LINKS`] links): refused.
//!
//! Links are followed by hand (`read_link`), which bypasses Linux's `protected_symlinks`: so,
//! as that rule does, a symlink in a sticky world-writable directory (`/tmp`) is followed only
//! if it belongs to the user or to the directory's owner. Another user's link planted at
//! `/tmp/out.exr` cannot make a render replace the user's own files.

use std::fs::Metadata;
use std::io;
use std::path::{Path, PathBuf};

use super::OutputError;
use super::staged::directory_of;

/// Links followed before a chain counts as a loop (Linux's own limit for one lookup).
pub(super) const MAX_LINKS: usize = 40;

/// The file an output path writes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Target {
    /// The file that is created or replaced: the path itself, or where its links lead.
    pub file: PathBuf,
    /// Whether `file` was reached through at least one symlink.
    pub linked: bool,
}

/// Resolves `path` (module docs). `flag` names the option in errors (`None` once staged, when
/// the error says `cannot write PATH`). Every refusal names `path`, where its links lead and
/// what the file there is.
pub(super) fn resolve(path: &Path, flag: Option<&str>) -> Result<Target, OutputError> {
    let unresolvable = |source| OutputError::Unresolvable {
        flag: flag.map(str::to_owned),
        path: path.to_path_buf(),
        source,
    };
    let mut file = path.to_path_buf();
    for links in 0..=MAX_LINKS {
        let meta = match std::fs::symlink_metadata(&file) {
            Ok(meta) => meta,
            // Nothing there (or a dangling link's end): the file to create.
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                return Ok(Target {
                    file,
                    linked: links > 0,
                });
            }
            Err(e) => return Err(unresolvable(e)),
        };
        if meta.file_type().is_symlink() {
            check_trusted_link(&file, &meta).map_err(unresolvable)?;
            // A relative link is relative to the directory holding it; an absolute one
            // replaces the path entirely (`join` does both). A bare name's directory is the
            // empty path, not `.`, so messages show `real.exr`, not `./real.exr`.
            let to = std::fs::read_link(&file).map_err(unresolvable)?;
            file = file.parent().unwrap_or(Path::new("")).join(to);
            continue;
        }
        if meta.is_file() {
            return Ok(Target {
                file,
                linked: links > 0,
            });
        }
        return Err(OutputError::NotRegular {
            flag: flag.map(str::to_owned),
            path: path.to_path_buf(),
            resolved: (links > 0).then_some(file),
            // In the words of the input side's refusals, so an input and an output that are
            // the same kind of file are described alike.
            kind: crate::files::file_kind(&meta.file_type()),
        });
    }
    Err(unresolvable(io::Error::other(format!(
        "a symlink loop (more than {MAX_LINKS} links in a row)"
    ))))
}

/// The `protected_symlinks` rule (module docs) for the link at `link` with metadata `meta`.
#[cfg(unix)]
fn check_trusted_link(link: &Path, meta: &Metadata) -> io::Result<()> {
    use std::os::unix::fs::MetadataExt;
    const STICKY: u32 = 0o1000;
    const WORLD_WRITABLE: u32 = 0o002;
    let dir = directory_of(link);
    let dir_meta = std::fs::metadata(dir)?;
    let shared = dir_meta.mode() & (STICKY | WORLD_WRITABLE) == STICKY | WORLD_WRITABLE;
    // SAFETY: geteuid has no preconditions and cannot fail.
    let me = unsafe { libc::geteuid() };
    if !shared || meta.uid() == me || meta.uid() == dir_meta.uid() {
        return Ok(());
    }
    Err(io::Error::new(
        io::ErrorKind::PermissionDenied,
        format!(
            "it is a symlink owned by another user in the shared directory {} (sticky and \
             world-writable), which is not followed",
            dir.display()
        ),
    ))
}

#[cfg(not(unix))]
fn check_trusted_link(_link: &Path, _meta: &Metadata) -> io::Result<()> {
    Ok(())
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use std::os::unix::fs::symlink;

    #[test]
    fn follows_chains_to_regular_and_dangling_ends() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::create_dir(d.join("sub")).unwrap();
        std::fs::write(d.join("sub/real.exr"), b"x").unwrap();
        symlink("sub/real.exr", d.join("a.exr")).unwrap();
        symlink("a.exr", d.join("b.exr")).unwrap();
        symlink("sub/none.exr", d.join("dangling.exr")).unwrap();
        let t = resolve(&d.join("b.exr"), None).unwrap();
        assert_eq!(
            t.file.canonicalize().unwrap(),
            d.join("sub/real.exr").canonicalize().unwrap()
        );
        assert!(t.linked);
        let t = resolve(&d.join("dangling.exr"), None).unwrap();
        assert_eq!(t.file, d.join("sub/none.exr"));
        let plain = d.join("new.exr");
        assert_eq!(
            resolve(&plain, None).unwrap(),
            Target {
                file: plain,
                linked: false
            }
        );
    }

    #[test]
    fn refuses_special_files_loops_and_says_where_links_lead() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        symlink("/dev/null", d.join("null.exr")).unwrap();
        symlink("null.exr", d.join("chain.exr")).unwrap();
        symlink("loop.exr", d.join("loop.exr")).unwrap();
        let err = resolve(&d.join("chain.exr"), Some("-o")).unwrap_err();
        let msg = err.to_string();
        assert!(matches!(err, OutputError::NotRegular { .. }), "{msg}");
        assert!(msg.contains("-o ") && msg.contains("chain.exr"), "{msg}");
        assert!(msg.contains("/dev/null"), "{msg}");
        assert!(
            msg.contains("not a regular file (a character device)"),
            "{msg}"
        );
        let err = resolve(d, None).unwrap_err();
        assert!(err.to_string().contains("(a directory)"), "{err}");
        let err = resolve(&d.join("loop.exr"), None).unwrap_err();
        assert!(matches!(err, OutputError::Unresolvable { .. }), "{err}");
    }

    /// Needs root to give a link another owner; elsewhere there is nothing to check.
    #[test]
    fn another_users_link_in_a_sticky_shared_directory_is_not_followed() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let shared = dir.path().join("tmp");
        std::fs::create_dir(&shared).unwrap();
        std::fs::set_permissions(&shared, std::fs::Permissions::from_mode(0o1777)).unwrap();
        std::fs::write(dir.path().join("mine.exr"), b"x").unwrap();
        let link = shared.join("out.exr");
        symlink("../mine.exr", &link).unwrap();
        assert!(
            resolve(&link, None).unwrap().linked,
            "one's own link is followed"
        );
        if std::os::unix::fs::lchown(&link, Some(54321), None).is_err() {
            return;
        }
        let err = resolve(&link, Some("-o")).unwrap_err();
        assert!(matches!(err, OutputError::Unresolvable { .. }), "{err}");
        let source = std::error::Error::source(&err).unwrap().to_string();
        assert!(source.contains("owned by another user"), "{source}");
    }
}
