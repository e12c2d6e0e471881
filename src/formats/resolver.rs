//! How readers get the bytes of the files a scene references (an OBJ mesh, an MTL file, a
//! texture, a glTF buffer): through a [`Resolver`], never by opening files themselves.

use std::path::Path;

use super::SceneError;

/// Reads file callback: the bytes of a file a scene references (an OBJ mesh, an MTL file, a
/// texture).
pub type Resolver<'a> = &'a dyn Fn(&Path) -> std::io::Result<Vec<u8>>;

/// The resolver of scenes on disk: reads `path` whole.
pub fn read_file_bytes(path: &Path) -> std::io::Result<Vec<u8>> {
    std::fs::read(path)
}

/// Reads a text file (a TOML, `.scn` or `.m` file), naming it in the error.
pub fn read_text(path: &Path) -> Result<String, SceneError> {
    std::fs::read_to_string(path).map_err(|source| SceneError::Read {
        path: path.to_path_buf(),
        source,
    })
}

/// Reads the scene file itself, naming it in the error.
pub fn read_file(path: &Path) -> Result<Vec<u8>, SceneError> {
    read_file_bytes(path).map_err(|source| SceneError::Read {
        path: path.to_path_buf(),
        source,
    })
}
