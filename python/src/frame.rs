//! Which ray origins the nearest-hit and any-hit queries trace as given: those inside the
//! scene's near region ([`lumis_core::accel::RayFrame`]); farther ones are moved near the
//! scene first, which rounds them (docs/hard-cases.md). `lumis.trimesh` answers those from the
//! all-hits query, which is exact on the caller's line from any distance.

use lumis_core::accel::AccelKind;
use numpy::{PyArray1, ToPyArray};
use pyo3::prelude::*;

use crate::arrays;
use crate::scene::PyScene;

/// For each origin (`(N, 3)` float32 or float64, rounded to float32 once): whether the
/// nearest-hit query traces a ray from it as given.
#[pyfunction]
pub fn near_origins<'py>(
    py: Python<'py>,
    scene: &PyScene,
    origins: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray1<bool>>> {
    let origins = arrays::points(origins, "origins")?;
    let world = py.detach(|| scene.world((AccelKind::Sah, scene.scene().settings().precision)));
    let frame = world.accel().frame();
    let near: Vec<bool> = origins.iter().map(|&o| frame.holds(o)).collect();
    Ok(near.to_pyarray(py))
}
