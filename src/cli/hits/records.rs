//! The files of `lumis hits`: rays in from an `.npy` array, one hit record per ray out to
//! another, plus the scene's triangles and spheres as lumis sees them after loading and
//! transforms. The queries and the row layouts are the library's ([`lumis_core::batch`], shared
//! with the Python package); this module writes the rows.
//!
//! Formats (float32, C order, world space; columns in [`lumis_core::batch`]):
//! - rays `(N, 8)`: origin xyz, direction xyz (any non-zero length; `t` is in units of it),
//!   `t_min`, `t_max`; hits count in `(t_min, t_max]`.
//! - hits `(N, 9)`: `t`, primitive id, object id, `u`, `v`, normal xyz, primitive kind
//!   ([`HitRecord::row`]); with `--instance-ids` `(N, 10)`, the instance id appended
//!   ([`HitRecord::row_with_instance`]; -1 outside any instance).
//! - triangles `(M, 10)`, spheres `(K, 5)`, spawn origins `(N, 6)`.
//!
//! Ids are stored as float32, exact up to 2^24.

use std::io::Write;
use std::path::Path;

use npyz::WriterBuilder;

pub use lumis_core::batch::{spawn_rows, sphere_rows, triangle_rows};
use lumis_io::output::{OutputError, StagedOutputs};
pub use lumis_io::rays::read_rays;

/// Why a result file could not be written; it names the file.
#[derive(Debug, thiserror::Error)]
pub enum HitsError {
    /// Writing a result failed.
    #[error(transparent)]
    Write(#[from] OutputError),
}

/// Stages `rows` as an `(len, N)` float32 C-order `.npy` array for `path` (written to a
/// temporary file beside it, renamed when the run's outputs are committed).
pub fn stage_rows<const N: usize>(
    staged: &mut StagedOutputs,
    path: &Path,
    rows: &[[f32; N]],
) -> Result<(), HitsError> {
    staged.stage(path, |w| {
        let io_err = |source| OutputError::Write {
            path: path.to_path_buf(),
            source,
        };
        let mut npy = npyz::WriteOptions::<f32>::new()
            .default_dtype()
            .shape(&[rows.len() as u64, N as u64])
            .writer(&mut *w)
            .begin_nd()
            .map_err(io_err)?;
        npy.extend(rows.iter().flatten().copied()).map_err(io_err)?;
        npy.finish().map_err(io_err)?;
        w.flush().map_err(io_err)
    })?;
    Ok(())
}
