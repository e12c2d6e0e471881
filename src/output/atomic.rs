//! Write-to-temporary-then-rename, so a target file is either the old image or the complete
//! new one, never a truncated mix.

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use super::OutputError;

/// Runs `encode` against a temporary file in the directory of `path`, then renames the
/// temporary file onto `path`.
///
/// The temporary file lives in the same directory because `rename` is only atomic within one
/// file system. On any error the temporary file is deleted (dropping `NamedTempFile` removes
/// it) and an existing file at `path` is left untouched. A symlink at `path` is replaced, not
/// written through.
pub fn write_atomically<F>(path: &Path, encode: F) -> Result<(), OutputError>
where
    F: FnOnce(&mut BufWriter<&mut File>) -> Result<(), OutputError>,
{
    let dir = match path.parent() {
        // A bare file name has an empty parent: it means the working directory.
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".lumis-").suffix(".tmp");
    // NamedTempFile defaults to 0o600; ask for 0o666 so the umask gives the renamed image the
    // same permissions as any other file the user creates.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut temp = builder
        .tempfile_in(dir)
        .map_err(|source| OutputError::CreateTemp {
            path: path.to_path_buf(),
            source,
        })?;

    let write_err = |source| OutputError::Write {
        path: path.to_path_buf(),
        source,
    };
    {
        let mut writer = BufWriter::new(temp.as_file_mut());
        encode(&mut writer)?;
        writer.into_inner().map_err(|e| write_err(e.into_error()))?;
    }
    // Sync before the rename so a crash cannot leave a renamed but empty file.
    temp.as_file().sync_all().map_err(write_err)?;

    temp.persist(path).map_err(|e| OutputError::Persist {
        path: path.to_path_buf(),
        source: e.error,
    })?;
    Ok(())
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

    #[test]
    fn failing_encoder_keeps_old_file_and_removes_temp() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("out.png");
        std::fs::write(&target, b"old image").unwrap();

        let result = write_atomically(&target, |w| {
            // Half-written data must never reach the target.
            w.write_all(b"partial").unwrap();
            w.flush().unwrap();
            Err(OutputError::UnsupportedExtension {
                path: target.clone(),
            })
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
}
