//! Reading an input file whole, refusing anything that is not a regular file.
//!
//! A FIFO blocks the reader until a writer appears (forever, for a hostile input), and a
//! character device such as `/dev/zero` never ends, so a plain `std::fs::read` either hangs or
//! grows until it runs out of memory. Every file lumis reads goes through [`read_regular`]:
//!
//! 1. `stat` (following symlinks): a directory, FIFO, socket or device is refused before it is
//!    opened;
//! 2. open with `O_NONBLOCK` on unix, so that a regular file swapped for a FIFO between the
//!    `stat` and the `open` cannot block the open, then check the *opened* file's type again;
//! 3. read at most the length the opened file reported plus one byte: a file that grows while
//!    it is read is refused instead of being followed without bound.

use std::fs::{File, FileType, Metadata};
use std::io::{self, Read};
use std::path::Path;

use super::inputs;

/// The bytes of the regular file at `path`, read whole; an `InvalidInput` error saying what
/// the file is (`not a regular file (a FIFO)`) for anything else.
pub fn read_regular(path: &Path) -> io::Result<Vec<u8>> {
    check_regular(&std::fs::metadata(path)?)?;
    let mut file = open_nonblocking(path)?;
    let meta = file.metadata()?;
    check_regular(&meta)?;
    let len = meta.len();
    let mut bytes = Vec::new();
    // A huge file is an error to report, not an allocation to abort on.
    let capacity = usize::try_from(len).map_err(|_| too_large(len))?;
    bytes
        .try_reserve_exact(capacity)
        .map_err(|_| too_large(len))?;
    (&mut file).take(len + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > len {
        return Err(io::Error::other(format!(
            "the file grew while being read (it had {len} bytes when opened)"
        )));
    }
    inputs::note(path, &meta);
    Ok(bytes)
}

/// `Ok` for a regular file; otherwise the error naming what it is.
fn check_regular(meta: &Metadata) -> io::Result<()> {
    if meta.is_file() {
        return Ok(());
    }
    Err(io::Error::new(
        io::ErrorKind::InvalidInput,
        format!("not a regular file ({})", file_kind(&meta.file_type())),
    ))
}

/// What a non-regular file is, for the message (inputs' and outputs').
pub(crate) fn file_kind(t: &FileType) -> &'static str {
    if t.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    "a special file"
}

fn too_large(len: u64) -> io::Error {
    io::Error::new(
        io::ErrorKind::OutOfMemory,
        format!("the file is too large to read into memory ({len} bytes)"),
    )
}

#[cfg(unix)]
fn open_nonblocking(path: &Path) -> io::Result<File> {
    use std::os::unix::fs::OpenOptionsExt;
    // O_NONBLOCK only changes how FIFOs and devices open and read; on a regular file it has no
    // effect, so the file can be read normally afterwards.
    std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(path)
}

#[cfg(not(unix))]
fn open_nonblocking(path: &Path) -> io::Result<File> {
    File::open(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_regular_file_whole() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.txt");
        std::fs::write(&path, b"hello").unwrap();
        assert_eq!(read_regular(&path).unwrap(), b"hello");
    }

    #[test]
    fn refuses_a_directory() {
        let dir = tempfile::tempdir().unwrap();
        let err = read_regular(dir.path()).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidInput);
        assert_eq!(err.to_string(), "not a regular file (a directory)");
    }

    #[cfg(unix)]
    #[test]
    fn refuses_dev_zero_at_once() {
        let err = read_regular(Path::new("/dev/zero")).unwrap_err();
        assert_eq!(err.to_string(), "not a regular file (a character device)");
    }

    #[test]
    fn missing_file_keeps_the_os_error() {
        let dir = tempfile::tempdir().unwrap();
        let err = read_regular(&dir.path().join("none")).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::NotFound);
    }
}
