//! A frame of a sequence in the output file names: `frame_####.exr` is `frame_0007.exr` at
//! frame 7. Its place in time in the EXR header is `exr/frame.rs`.

use std::path::{Path, PathBuf};

/// `path` with its last run of `#` replaced by `number`, zero-padded to the run's length:
/// Blender's convention, so `out/frame_####.exr` at frame 7 is `out/frame_0007.exr`. A number
/// with more digits than the run is written whole; a path without `#` is returned unchanged.
/// Only a path that is not valid Unicode and holds a `#` cannot be numbered.
pub fn numbered_path(path: &Path, number: u32) -> Result<PathBuf, String> {
    if !path.as_os_str().as_encoded_bytes().contains(&b'#') {
        return Ok(path.to_path_buf());
    }
    let Some(text) = path.to_str() else {
        return Err(format!(
            "{}: a path that is not valid Unicode cannot be numbered by its #",
            path.display()
        ));
    };
    let end = text.rfind('#').map_or(0, |i| i + 1);
    let start = text[..end].trim_end_matches('#').len();
    let width = end - start;
    Ok(PathBuf::from(format!(
        "{}{number:0width$}{}",
        &text[..start],
        &text[end..]
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_last_run_of_hashes_becomes_the_padded_frame_number() {
        let n = |p: &str, f| numbered_path(Path::new(p), f).unwrap();
        assert_eq!(n("out/frame_####.exr", 7), Path::new("out/frame_0007.exr"));
        assert_eq!(n("frame_#.png", 12), Path::new("frame_12.png"));
        assert_eq!(n("f_##.exr", 12345), Path::new("f_12345.exr"));
        assert_eq!(n("shot#2/f_###.exr", 3), Path::new("shot#2/f_003.exr"));
        assert_eq!(n("####/beauty.exr", 42), Path::new("0042/beauty.exr"));
        assert_eq!(n("still.exr", 9), Path::new("still.exr"));
        assert_eq!(n("#", 0), Path::new("0"));
    }

    #[cfg(unix)]
    #[test]
    fn a_non_unicode_path_is_numbered_only_when_it_needs_to_be() {
        use std::ffi::OsStr;
        use std::os::unix::ffi::OsStrExt;
        let plain = Path::new(OsStr::from_bytes(b"caf\xe9.exr"));
        assert_eq!(numbered_path(plain, 1).unwrap(), plain);
        let hashed = Path::new(OsStr::from_bytes(b"caf\xe9_##.exr"));
        assert!(numbered_path(hashed, 1).unwrap_err().contains("Unicode"));
    }
}
