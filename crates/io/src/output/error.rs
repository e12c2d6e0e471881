//! Why an output could not be written, or may not be: every variant names the target path
//! (and, for the checks before a run, the flag that gave it).

use std::path::{Path, PathBuf};

/// Why an output could not be written. Every variant names the target path.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The film has no pixels; neither format can hold a 0-pixel image.
    #[error("cannot write {}: the film is empty ({width}x{height} pixels)", path.display())]
    EmptyFilm {
        /// Target path.
        path: PathBuf,
        /// Film width in pixels.
        width: u32,
        /// Film height in pixels.
        height: u32,
    },
    /// The extension is neither `.exr` nor `.png`.
    #[error("cannot write {}: unknown image extension (expected .exr or .png)", path.display())]
    UnsupportedExtension {
        /// Target path.
        path: PathBuf,
    },
    /// The PNG exposure is NaN or infinite.
    #[error("cannot write {}: exposure {stops} stops is not a finite number", path.display())]
    BadExposure {
        /// Target path.
        path: PathBuf,
        /// The rejected exposure in stops.
        stops: f32,
    },
    /// The temporary file next to the target could not be created (missing directory,
    /// no permission, read-only file system).
    #[error("cannot create a temporary file next to {}", path.display())]
    CreateTemp {
        /// Target path.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The OpenEXR encoder failed.
    #[error("failed to encode OpenEXR image {}", path.display())]
    Exr {
        /// Target path.
        path: PathBuf,
        /// The encoder's error.
        #[source]
        source: ::exr::error::Error,
    },
    /// The PNG encoder failed.
    #[error("failed to encode PNG image {}", path.display())]
    Png {
        /// Target path.
        path: PathBuf,
        /// The encoder's error.
        #[source]
        source: image::ImageError,
    },
    /// Flushing or syncing the finished temporary file failed.
    #[error("failed to write image data for {}", path.display())]
    Write {
        /// Target path.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The film holds a NaN or infinite sample; nothing was written.
    #[error("cannot write {}", path.display())]
    NonFinite {
        /// Target path.
        path: PathBuf,
        /// How many samples, and the first.
        #[source]
        source: lumis_core::film::NonFinite,
    },
    /// The finished temporary file could not be renamed onto the target (for example, the
    /// target became a directory after the last check). The temporary file has been removed.
    #[error("cannot move the finished image into place at {}", path.display())]
    Persist {
        /// Target path.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The directory an output goes in does not exist (or is not a directory).
    #[error("{flag} {}: the directory {} does not exist", shown(path, resolved), dir.display())]
    NoDirectory {
        /// The option that named the output (`-o`, `--png`, ...).
        flag: String,
        /// Target path.
        path: PathBuf,
        /// Where its symlinks lead, when it is a (dangling) symlink.
        resolved: Option<PathBuf>,
        /// The directory of the file to create.
        dir: PathBuf,
    },
    /// The output is, or its symlinks lead to, a FIFO, a device, a socket or a directory: it
    /// is refused, not opened or replaced.
    #[error(
        "{}{}: not a regular file ({kind}); outputs are written only to regular files (or \
         through symlinks to them), so it was left as it is",
        lead(flag),
        shown(path, resolved)
    )]
    NotRegular {
        /// The option that named the output; `None` for the check when it is written.
        flag: Option<String>,
        /// Target path.
        path: PathBuf,
        /// Where its symlinks lead, when it is a symlink.
        resolved: Option<PathBuf>,
        /// What the file is: `a FIFO`, `a character device`, ...
        kind: &'static str,
    },
    /// The output's symlinks could not be followed: a loop, a link that may not be trusted,
    /// or an error examining them.
    #[error("{}{}: cannot tell which file to write", lead(flag), path.display())]
    Unresolvable {
        /// The option that named the output; `None` for the check when it is written.
        flag: Option<String>,
        /// Target path.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The output's symlinks lead somewhere else than when it was staged: it changed during
    /// the run, and no output was renamed into place.
    #[error(
        "cannot write {}: it changed during the run (it now leads to {}, not {}), so no \
         output was written",
        path.display(),
        now.display(),
        was.display()
    )]
    TargetChanged {
        /// Target path.
        path: PathBuf,
        /// The file it led to when staged.
        was: PathBuf,
        /// The file it leads to now.
        now: PathBuf,
    },
    /// The output path names a directory by its form (`x/..`, `/`); an existing directory at
    /// a file name is [`NotRegular`](Self::NotRegular).
    #[error("{flag} {}: is a directory", path.display())]
    IsDirectory {
        /// The option that named the output.
        flag: String,
        /// Target path.
        path: PathBuf,
    },
    /// No file can be created in the output's directory (permissions, read-only file system).
    #[error("{flag} {}: cannot create files in {}", path.display(), dir.display())]
    NotWritable {
        /// The option that named the output.
        flag: String,
        /// Target path.
        path: PathBuf,
        /// Its directory.
        dir: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The output is a file the run reads (the scene, a texture, the rays).
    #[error(
        "{flag} {}: is an input of this run (read as {}); writing it would destroy it, so \
         choose another file",
        path.display(),
        input.display()
    )]
    IsInput {
        /// The option that named the output.
        flag: String,
        /// Target path.
        path: PathBuf,
        /// The input it is, as the loader named it.
        input: PathBuf,
    },
    /// Two outputs are the same file.
    #[error("{flag} {}: is the same file as {other_flag} {}", path.display(), other.display())]
    SameFile {
        /// The option that named the later output.
        flag: String,
        /// Its path.
        path: PathBuf,
        /// The option that named the earlier output.
        other_flag: String,
        /// Its path.
        other: PathBuf,
    },
}

/// How an error starts: with the option that named the output, or `cannot write` once staged.
fn lead(flag: &Option<String>) -> String {
    match flag {
        Some(flag) => format!("{flag} "),
        None => "cannot write ".to_owned(),
    }
}

/// An output path as messages show it: with where its symlinks lead, if it is one.
fn shown(path: &Path, resolved: &Option<PathBuf>) -> String {
    match resolved {
        Some(to) => format!("{} (a symlink leading to {})", path.display(), to.display()),
        None => path.display().to_string(),
    }
}
