//! The scene hash of `lumis/sceneHash`: which files a render read, by content, and how it
//! loaded them.
//!
//! Each input file is hashed on its own and the digests are sorted before they are combined,
//! so neither the order the loader happened to read them in nor the paths they sit at (a
//! shared filesystem mounted elsewhere on another node) change the hash; their bytes and the
//! load options do.

use std::io::{self, Read};
use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use crate::files::InputFile;
use crate::formats::{LoadOptions, Override};

/// SHA-256 (lowercase hex) over the contents of `inputs` and `load_options` (a text the caller
/// makes of every option that changes what is loaded: `-D` overrides, glTF scene and camera
/// choice, up axis; for the built-in scene, a name for it).
pub fn scene_hash(inputs: &[InputFile], load_options: &str) -> io::Result<String> {
    let digests: Vec<String> = file_digests(inputs)?.into_iter().map(|(_, d)| d).collect();
    Ok(scene_hash_of(digests, load_options))
}

/// [`scene_hash`] from the files' digests ([`file_digests`]), in any order.
pub fn scene_hash_of(mut digests: Vec<String>, load_options: &str) -> String {
    digests.sort_unstable();
    let mut hasher = Sha256::new();
    hasher.update(b"lumis scene hash 1\n");
    // Length-prefixed, so that no two different option texts and file lists hash alike.
    hasher.update((load_options.len() as u64).to_le_bytes());
    hasher.update(load_options.as_bytes());
    for d in &digests {
        hasher.update(d.as_bytes());
    }
    hex(&hasher.finalize())
}

/// The text of the load options that [`scene_hash`] hashes: what decides what is loaded
/// besides the files (`from_file`: a scene file rather than the built-in scene), one
/// `name: value` per line, the same for the command line and Python.
pub fn load_options_text(from_file: bool, defines: &[Override], o: &LoadOptions) -> String {
    let source = if from_file {
        "file"
    } else {
        "the built-in default scene"
    };
    let defines: Vec<String> = defines.iter().map(ToString::to_string).collect();
    let or = |v: Option<usize>, none: &str| v.map_or(none.to_string(), |n| n.to_string());
    let mut text = format!(
        "source: {source}\ndefines: {}\ngltf scene: {}\ncamera: {}\nauto camera: {}\nup: {}\n",
        defines.join("; "),
        or(o.scene, "default"),
        or(o.camera, "first"),
        o.auto_camera,
        o.up.name()
    );
    if o.flatten_instances {
        text.push_str("flatten instances: true\n");
    }
    text
}

/// Each of `inputs` (the path as the reader was given it) with the SHA-256 (lowercase hex) of
/// its contents, in the order read.
pub fn file_digests(inputs: &[InputFile]) -> io::Result<Vec<(PathBuf, String)>> {
    inputs
        .iter()
        .map(|input| Ok((input.path.clone(), file_digest(&input.path)?)))
        .collect()
}

/// The SHA-256 (lowercase hex) of the file at `path`.
pub fn file_digest(path: &Path) -> io::Result<String> {
    let mut file = std::fs::File::open(path)?;
    let mut hasher = Sha256::new();
    let mut buffer = vec![0u8; 1 << 16];
    loop {
        let n = file.read(&mut buffer)?;
        if n == 0 {
            break;
        }
        hasher.update(&buffer[..n]);
    }
    Ok(hex(&hasher.finalize()))
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input(path: &Path) -> InputFile {
        InputFile {
            path: path.to_path_buf(),
            canonical: path.to_path_buf(),
            id: None,
        }
    }

    #[test]
    fn contents_and_options_count_order_and_paths_do_not() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b, c) = (
            dir.path().join("a"),
            dir.path().join("b"),
            dir.path().join("c"),
        );
        std::fs::write(&a, "scene").unwrap();
        std::fs::write(&b, "mesh").unwrap();
        std::fs::write(&c, "scene").unwrap();
        let h = |files: &[&Path], opts| {
            let inputs: Vec<InputFile> = files.iter().map(|p| input(p)).collect();
            scene_hash(&inputs, opts).unwrap()
        };
        let base = h(&[&a, &b], "");
        assert_eq!(base.len(), 64);
        assert_eq!(h(&[&b, &a], ""), base, "order");
        assert_eq!(h(&[&c, &b], ""), base, "path");
        assert_ne!(h(&[&a, &b], "-D x=1"), base, "options");
        std::fs::write(&b, "mesh!").unwrap();
        assert_ne!(h(&[&a, &b], ""), base, "content");
        // The empty-input hash of SHA-256 itself, as a check of the digest and the hex.
        assert_eq!(
            hex(&Sha256::digest(b"")),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
        );
    }
}
