//! Renders to numpy (filled in below).

use pyo3::exceptions::PyNotImplementedError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use lumis_core::accel::AccelKind;
use lumis_core::geometry::Precision;

use crate::scene::PyScene;

/// What `Scene.render` asks for.
#[allow(dead_code)]
pub struct Request {
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub spp: Option<u32>,
    pub max_depth: Option<u32>,
    pub aovs: Vec<String>,
    pub seed: u64,
    pub threads: Option<usize>,
    pub exposure: Option<f32>,
    pub accel: AccelKind,
    pub precision: Option<Precision>,
    pub transparent: bool,
    pub auto_exposure: bool,
}

/// Renders `scene` as `request` says.
pub fn render<'py>(
    _py: Python<'py>,
    _scene: &PyScene,
    _request: &Request,
) -> PyResult<Bound<'py, PyDict>> {
    Err(PyNotImplementedError::new_err("render"))
}
