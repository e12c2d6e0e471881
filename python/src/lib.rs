//! `lumis._lumis`: the compiled half of the `lumis` Python package (the `lumis-rt`
//! distribution). The Python half (`python/lumis/`) holds the public classes, their docstrings
//! and the argument conversions; this module does the work: loading ([`load`]), batch ray
//! queries on numpy arrays ([`scene::PyScene`], through [`lumis_core::batch`], the same function
//! as `lumis hits`) and renders.
//!
//! Every long call releases the GIL and runs on rayon's pool (the global one, or a pool of the
//! requested size, cached).

mod arrays;
mod builder;
mod choices;
mod contains;
mod errors;
mod frame;
mod hits;
mod provenance;
mod rays;
mod render;
mod scene;
mod source;
mod threads;

use pyo3::prelude::*;

use lumis_io::files::record_inputs;
use lumis_io::formats::{LoadOptions, Override};

pub use errors::{RayError, SceneError};

/// Loads a scene file (`.toml`, `.scn`, `.obj`, `.gltf`, `.glb`) with `-D`-style overrides
/// (`"KEY=VALUE"` strings, applied in order) and the model-file options of `lumis render`.
/// Every file the load reads is hashed (SHA-256), for the scene's pickle; `expect_files`
/// (what a pickle recorded: `(path, digest)` pairs) refuses, by name, a file that changed.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[pyo3(signature = (path, *, defines=Vec::new(), gltf_scene=None, camera=None, up=None, auto_camera=false, frame=None, flatten_instances=false, expect_files=None))]
fn load(
    py: Python<'_>,
    path: std::path::PathBuf,
    defines: Vec<String>,
    gltf_scene: Option<usize>,
    camera: Option<usize>,
    up: Option<&str>,
    auto_camera: bool,
    frame: Option<u32>,
    flatten_instances: bool,
    expect_files: Option<Vec<(std::path::PathBuf, String)>>,
) -> PyResult<scene::PyScene> {
    let overrides = defines
        .iter()
        .map(|d| {
            d.parse::<Override>()
                .map_err(|e| SceneError::new_err(format!("-D {d}: {e}")))
        })
        .collect::<PyResult<Vec<_>>>()?;
    let up = choices::up(up)?;
    if camera.is_some() && auto_camera {
        return Err(pyo3::exceptions::PyValueError::new_err(
            "camera and auto_camera conflict (as --camera and --auto-camera do)",
        ));
    }
    let options = LoadOptions {
        scene: gltf_scene,
        camera,
        up,
        auto_camera,
        frame,
        flatten_instances,
    };
    let absolute = std::path::absolute(&path).unwrap_or_else(|_| path.clone());
    let (scene, digests) = py.detach(|| {
        let (loaded, inputs) =
            record_inputs(|| lumis_io::formats::load_with_overrides(&path, &options, &overrides));
        let digests = loaded.as_ref().ok().map(|_| source::digests(&inputs));
        (loaded, digests)
    });
    if let Some(expected) = &expect_files {
        let now = match &digests {
            Some(Ok(d)) => Some(d.as_slice()),
            _ => None,
        };
        if let Some(why) = source::changed_files(&absolute, expected, now) {
            return Err(SceneError::new_err(why));
        }
    }
    let scene = scene.map_err(|e| errors::scene_error(&e))?;
    let digests = digests.expect("hashed after a load")?;
    let file = source::FileSource {
        given: path,
        absolute,
        defines,
        options,
        digests,
    };
    Ok(scene::PyScene::new(scene, source::Source::File(file)))
}

/// The extension module.
#[pymodule]
fn _lumis(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(contains::contains, m)?)?;
    m.add_function(wrap_pyfunction!(contains::containment_methods, m)?)?;
    m.add_function(wrap_pyfunction!(frame::near_origins, m)?)?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<builder::PySceneBuilder>()?;
    m.add("SceneError", m.py().get_type::<SceneError>())?;
    m.add("RayError", m.py().get_type::<RayError>())?;
    m.add("HIT_COLUMNS", lumis_core::batch::HIT_COLUMNS)?;
    m.add("ALL_HITS_AVAILABLE", scene::ALL_HITS_AVAILABLE)?;
    m.add("CHOICES", choices::names(m.py())?)?;
    Ok(())
}
