//! Which files a run read: the scene and everything it references (meshes, MTL files,
//! textures, glTF buffers and images, `.m` meshes), plus anything else the caller reads through
//! [`read_regular`](super::read_regular) (the rays of `lumis hits`). The CLI refuses an output
//! that is one of them, so a run can never overwrite its own input.
//!
//! The log is kept per thread while [`record_inputs`] runs: the loaders are single-threaded
//! and every file they read passes through the disk resolver, so noting it there sees every
//! read without threading a log through each loader's signature.

use std::cell::RefCell;
use std::fs::Metadata;
use std::path::{Path, PathBuf};

/// A file read during [`record_inputs`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InputFile {
    /// The path as the reader was given it.
    pub path: PathBuf,
    /// The path with symlinks and `.`/`..` resolved (the given path if that fails).
    pub canonical: PathBuf,
    /// Device and inode on unix, so a hard link to the file is recognised too.
    pub id: Option<(u64, u64)>,
}

thread_local! {
    static LOG: RefCell<Option<Vec<InputFile>>> = const { RefCell::new(None) };
}

/// Runs `f` and returns its result with every file read through the disk resolver meanwhile,
/// in the order first read, each once.
pub fn record_inputs<T>(f: impl FnOnce() -> T) -> (T, Vec<InputFile>) {
    // Nested recordings: the inner one starts empty; its files are also the outer one's.
    let outer = LOG.with(|log| log.borrow_mut().replace(Vec::new()));
    let result = f();
    let files = LOG.with(|log| log.borrow_mut().take()).unwrap_or_default();
    if let Some(mut outer) = outer {
        for file in &files {
            if !outer.contains(file) {
                outer.push(file.clone());
            }
        }
        LOG.with(|log| *log.borrow_mut() = Some(outer));
    }
    (result, files)
}

/// Notes that `path` (with metadata `meta`, of the opened file) was read, if recording.
pub(super) fn note(path: &Path, meta: &Metadata) {
    LOG.with(|log| {
        if let Some(files) = log.borrow_mut().as_mut() {
            let file = InputFile {
                path: path.to_path_buf(),
                canonical: std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()),
                id: file_id(meta),
            };
            if !files.contains(&file) {
                files.push(file);
            }
        }
    });
}

/// Device and inode of `meta` (unix only).
pub fn file_id(meta: &Metadata) -> Option<(u64, u64)> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        Some((meta.dev(), meta.ino()))
    }
    #[cfg(not(unix))]
    {
        let _ = meta;
        None
    }
}

#[cfg(test)]
mod tests {
    use super::super::read_regular;
    use super::*;

    #[test]
    fn records_each_file_once_and_only_while_recording() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a"), dir.path().join("b"));
        std::fs::write(&a, b"1").unwrap();
        std::fs::write(&b, b"2").unwrap();
        read_regular(&a).unwrap();
        let ((), files) = record_inputs(|| {
            read_regular(&b).unwrap();
            read_regular(&b).unwrap();
            let ((), inner) = record_inputs(|| {
                read_regular(&a).unwrap();
            });
            assert_eq!(inner.len(), 1);
        });
        let names: Vec<_> = files.iter().map(|f| f.path.clone()).collect();
        assert_eq!(names, [b, a]);
        assert!(files.iter().all(|f| f.canonical.is_absolute()));
    }
}
