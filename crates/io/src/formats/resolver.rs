//! How readers get the bytes of the files a scene references (an OBJ mesh, an MTL file, a
//! texture, a glTF buffer): through a [`Resolver`], never by opening files themselves.
//!
//! The disk versions below read through [`read_regular`]: FIFOs, devices and directories are
//! refused instead of hanging or exhausting memory, and every file read is noted for
//! [`record_inputs`](crate::files::record_inputs).

use std::path::Path;

use super::SceneError;
use crate::files::read_regular;

/// Reads file callback: the bytes of a file a scene references (an OBJ mesh, an MTL file, a
/// texture).
pub type Resolver<'a> = &'a dyn Fn(&Path) -> std::io::Result<Vec<u8>>;

/// The resolver of scenes on disk: reads the regular file `path` whole.
pub fn read_file_bytes(path: &Path) -> std::io::Result<Vec<u8>> {
    read_regular(path)
}

/// Reads a text file (a TOML, `.scn` or `.m` file), naming it in the error.
pub fn read_text(path: &Path) -> Result<String, SceneError> {
    String::from_utf8(read_file(path)?).map_err(|_| SceneError::Read {
        path: path.to_path_buf(),
        source: std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "stream did not contain valid UTF-8",
        ),
    })
}

/// Reads the scene file itself, naming it in the error.
pub fn read_file(path: &Path) -> Result<Vec<u8>, SceneError> {
    read_file_bytes(path).map_err(|source| SceneError::Read {
        path: path.to_path_buf(),
        source,
    })
}
