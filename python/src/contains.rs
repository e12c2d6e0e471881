//! `Scene.contains`: point containment ([`lumis_core::scene::World::containment`]; the rules
//! are in docs/hard-cases.md, "Point containment"), without the GIL, on rayon's pool.

use lumis_core::accel::AccelKind;
use lumis_core::geometry::Precision;
use lumis_core::scene::ContainmentMethod;
use numpy::{PyArray1, ToPyArray};
use pyo3::prelude::*;

use crate::arrays;
use crate::scene::PyScene;
use crate::threads;

/// The name Python reports for a method.
fn method_name(m: ContainmentMethod) -> &'static str {
    match m {
        ContainmentMethod::Exact => "exact",
        ContainmentMethod::WindingNumber => "winding_number",
    }
}

/// Two bool arrays of one length: the answers, and which of them the winding number gave.
type Answers<'py> = (Bound<'py, PyArray1<bool>>, Bound<'py, PyArray1<bool>>);

/// Whether each point of `points` (`(N, 3)` float32 or float64, rounded to float32 once) lies
/// inside the scene's solids, and whether the winding number decided it: two bool arrays.
#[pyfunction]
#[pyo3(signature = (scene, points, *, threads=None))]
pub fn contains<'py>(
    py: Python<'py>,
    scene: &PyScene,
    points: &Bound<'py, PyAny>,
    threads: Option<usize>,
) -> PyResult<Answers<'py>> {
    let points = arrays::points(points, "points")?;
    let answers = py.detach(|| {
        threads::run(threads, || {
            let world = scene.world((AccelKind::Sah, Precision::Watertight));
            world.containment(&points)
        })
    })?;
    // Points were checked finite above, the only thing containment refuses.
    let answers = answers.map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
    let inside: Vec<bool> = answers.iter().map(|c| c.inside).collect();
    let winding: Vec<bool> = answers
        .iter()
        .map(|c| c.method == ContainmentMethod::WindingNumber)
        .collect();
    Ok((inside.to_pyarray(py), winding.to_pyarray(py)))
}

/// How each object answers containment queries, by object id: `"exact"` (a closed mesh or a
/// sphere) or `"winding_number"` (a mesh that is not closed).
#[pyfunction]
pub fn containment_methods(py: Python<'_>, scene: &PyScene) -> Vec<&'static str> {
    let world = py.detach(|| scene.world((AccelKind::Sah, Precision::Watertight)));
    world
        .containment_methods()
        .iter()
        .map(|&m| method_name(m))
        .collect()
}
