//! Ray batches for `lumis hits`: an `(N, 8)` float32 `.npy` array, one ray per row (origin
//! xyz, direction xyz, `t_min`, `t_max`), read and checked here so that the CLI and the fuzz
//! targets go through the same entry point, [`read_rays`].
//!
//! Every size the file declares is checked against the bytes present before anything is
//! allocated: the header length, and the shape, whose row count times the row size must equal
//! the data bytes exactly (no overflow, no truncation, no trailing bytes).

mod npy;

use std::path::{Path, PathBuf};

use lumis_core::batch::check_rays;
pub use lumis_core::batch::{RAY_COLUMNS, RayRow};

/// Why a ray file could not be read. Every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum RaysError {
    /// The file could not be read.
    #[error("cannot read {}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The file is not an `.npy` array of the expected dtype, shape or order.
    #[error("{}: {message}", path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// What was found and what was expected.
        message: String,
    },
    /// One ray is unusable.
    #[error("{}: ray {row}: {message}", path.display())]
    BadRay {
        /// The file.
        path: PathBuf,
        /// Row index (0-based).
        row: usize,
        /// What is wrong with it, and the range.
        message: String,
    },
}

/// Reads the `(N, 8)` float32 C-order `.npy` file at `path` and checks every ray (see
/// [`parse_rays`]).
pub fn read_rays(path: &Path) -> Result<Vec<RayRow>, RaysError> {
    let bytes = crate::files::read_regular(path).map_err(|source| RaysError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    parse_rays(&bytes, path)
}

/// The rays of `.npy` bytes: float32 (either byte order), C order, shape `(N, 8)`, exactly
/// `N * 32` data bytes; every ray inside the query domain ([`check_rays`]: a finite origin, a
/// finite non-zero direction, `t_min`, `t_max` not NaN; the first bad row is named). `path`
/// names the file in errors.
pub fn parse_rays(bytes: &[u8], path: &Path) -> Result<Vec<RayRow>, RaysError> {
    let format = |message: String| RaysError::Format {
        path: path.to_path_buf(),
        message,
    };
    let header =
        npy::parse_header(bytes).map_err(|e| format(format!("not a valid .npy file ({e})")))?;
    let big_endian = match header.descr.as_str() {
        "<f4" => false,
        ">f4" => true,
        other => {
            return Err(format(format!(
                "dtype is {other}; expected float32 ('<f4')"
            )));
        }
    };
    let shape = &header.shape;
    if shape.len() != 2 || shape[1] != RAY_COLUMNS as u64 {
        return Err(format(format!(
            "shape is {shape:?}; expected (N, {RAY_COLUMNS}): origin xyz, direction xyz, t_min, t_max"
        )));
    }
    if header.fortran_order {
        return Err(format("Fortran-order array; expected C order".into()));
    }
    let data = &bytes[header.data_start..];
    let row_bytes = (RAY_COLUMNS * 4) as u64;
    let declared = shape[0].checked_mul(row_bytes);
    if declared != Some(data.len() as u64) {
        let what = match declared {
            Some(n) if n > data.len() as u64 => format!("truncated data: {n} bytes declared"),
            Some(n) => format!(
                "{} trailing bytes after the {n} declared",
                data.len() as u64 - n
            ),
            None => "the row count overflows".into(),
        };
        return Err(format(format!(
            "{what}; the shape ({}, {RAY_COLUMNS}) needs {} bytes of float32, the file has {} \
             after its header",
            shape[0],
            declared.map_or_else(|| "more than 2^64".into(), |n| n.to_string()),
            data.len()
        )));
    }
    // The size now matches bytes that exist, so the allocation is bounded by the file.
    let rays: Vec<RayRow> = data
        .chunks_exact(RAY_COLUMNS * 4)
        .map(|row| {
            std::array::from_fn(|i| {
                let b = [row[4 * i], row[4 * i + 1], row[4 * i + 2], row[4 * i + 3]];
                if big_endian {
                    f32::from_be_bytes(b)
                } else {
                    f32::from_le_bytes(b)
                }
            })
        })
        .collect();
    check_rays(&rays[..]).map_err(|(row, e)| RaysError::BadRay {
        path: path.to_path_buf(),
        row,
        message: e.to_string(),
    })?;
    Ok(rays)
}
