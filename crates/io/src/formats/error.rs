//! Errors of the scene loaders. Every variant names the file it comes from; syntax errors carry
//! the line and column, semantic errors the element (`sphere[3]`, `mesh[1] "teapot"`).
//!
//! `Display` gives this error's own message; the underlying cause (an I/O error, the OBJ file
//! a mesh failed to load) is its `source()`, so print the whole chain (`{:#}` with anyhow).

use std::path::{Path, PathBuf};

/// Why a scene (or a file it references) could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("cannot read {}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The I/O failure.
        #[source]
        source: std::io::Error,
    },
    /// The text is not valid TOML or does not match the scene schema.
    #[error("{}: line {line}, column {column}: {message}", path.display())]
    Parse {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the offending text.
        line: usize,
        /// 1-based column (in characters) of the offending text.
        column: usize,
        /// What the parser found and what it expected.
        message: String,
    },
    /// A well-formed element has a bad value or a dangling reference.
    #[error("{}: {element}: {message}", path.display())]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// The element, e.g. `sphere[3]`, `materials.glass`, `render`.
        element: String,
        /// What is wrong with it.
        message: String,
    },
    /// A file referenced by an element failed to load; the cause is the `source`.
    #[error("{}: {element}: cannot load {}", path.display(), file.display())]
    Asset {
        /// The scene file.
        path: PathBuf,
        /// The element that references the file.
        element: String,
        /// The referenced file, as resolved against the scene's folder.
        file: PathBuf,
        /// Why it failed.
        #[source]
        source: Box<SceneError>,
    },
    /// A line of a line-oriented file (`.scn`, `.m`) is malformed or refers to something
    /// missing.
    #[error("{}:{line}: {message}", path.display())]
    Line {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// What was found and what was expected.
        message: String,
    },
    /// The OBJ file is malformed.
    #[error("{}: invalid OBJ: {message}", path.display())]
    Obj {
        /// The OBJ file.
        path: PathBuf,
        /// What tobj or the mesh validation reported.
        message: String,
    },
    /// A file referenced from a line of a line-oriented file (a `.scn` `model`) failed to
    /// load; the cause is the `source`.
    #[error("{}:{line}: cannot load {}", path.display(), file.display())]
    LineAsset {
        /// The referencing file.
        path: PathBuf,
        /// 1-based line of the reference.
        line: usize,
        /// The referenced file.
        file: PathBuf,
        /// Why it failed.
        #[source]
        source: Box<SceneError>,
    },
    /// The glTF file as a whole is unreadable (bad GLB container, invalid JSON, a schema
    /// violation); errors in one element use [`SceneError::Invalid`] with that element.
    #[error("{}: invalid glTF: {message}", path.display())]
    Gltf {
        /// The .gltf or .glb file.
        path: PathBuf,
        /// What is wrong, with the JSON path where the parser gives one.
        message: String,
    },
    /// The file extension names no format this crate reads.
    #[error("{}: unknown scene format (expected .toml, .scn, .obj, .gltf or .glb)", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
}

impl SceneError {
    /// A semantic error in element `element` of file `path`.
    pub(crate) fn invalid(
        path: &Path,
        element: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        Self::Invalid {
            path: path.to_path_buf(),
            element: element.into(),
            message: message.into(),
        }
    }

    /// A parse error at byte offset `offset` of `text`, converted to a 1-based line and column.
    pub(crate) fn parse_at(path: &Path, text: &str, offset: usize, message: &str) -> Self {
        let mut offset = offset.min(text.len());
        while !text.is_char_boundary(offset) {
            offset -= 1;
        }
        let before = &text[..offset];
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        Self::Parse {
            path: path.to_path_buf(),
            line: before.matches('\n').count() + 1,
            column: before[line_start..].chars().count() + 1,
            message: message.trim().to_string(),
        }
    }
}
