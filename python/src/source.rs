//! Where a scene came from, which is what it pickles as: a file (its absolute path, the
//! defines and load options, and the SHA-256 of every file the load read, so that unpickling
//! refuses a changed file by name instead of answering for other geometry), or the builder's
//! steps with the arrays the scene holds (float32 vertices, uint32 faces, spheres, float64
//! instance matrices), which rebuild it exactly.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use lumis_core::scene::Scene;
use lumis_io::files::InputFile;
use lumis_io::formats::LoadOptions;
use numpy::ndarray::{Array1, Array2};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::errors::SceneError;

/// One call of the builder, in order (the data lives in the built scene).
#[derive(Clone, Debug)]
pub enum Step {
    Mesh { name: String },
    Sphere { name: String },
    Prototype,
    Instance { prototype: u32, name: String },
}

/// A file scene's identity: what reloads it, and the digests of what it read.
#[derive(Clone, Debug)]
pub struct FileSource {
    /// The path as given to `load` (what `Scene.path` shows).
    pub given: PathBuf,
    /// The path made absolute at load time (what a pickle reloads, from any directory).
    pub absolute: PathBuf,
    pub defines: Vec<String>,
    pub options: LoadOptions,
    /// Every file the load read (the scene file first) and its SHA-256, lowercase hex.
    pub digests: Vec<(PathBuf, String)>,
}

/// Where a [`crate::scene::PyScene`] came from.
#[derive(Clone, Debug)]
pub enum Source {
    File(FileSource),
    Arrays(Vec<Step>),
}

/// SHA-256 of the file at `path`, lowercase hex (the digest `lumis/replay` records too).
pub use lumis_io::farm::file_digest;

/// The absolute path (made so now, against the current directory, as the load read it) and
/// digest of each of `inputs`, or a [`SceneError`] naming the file that cannot be read.
pub fn digests(inputs: &[InputFile]) -> PyResult<Vec<(PathBuf, String)>> {
    inputs
        .iter()
        .map(|f| {
            let digest = file_digest(&f.path).map_err(|e| {
                SceneError::new_err(format!("{}: cannot be hashed: {e}", f.path.display()))
            })?;
            let absolute = std::path::absolute(&f.path).unwrap_or_else(|_| f.path.clone());
            Ok((absolute, digest))
        })
        .collect()
}

/// Why the files a pickle recorded (`expected`) are not the ones read now (`now`: `None` when
/// the load failed, then the recorded files are hashed afresh to tell why), or `None`.
pub fn changed_files(
    pickled: &Path,
    expected: &[(PathBuf, String)],
    now: Option<&[(PathBuf, String)]>,
) -> Option<String> {
    let hashed_now: Vec<(PathBuf, std::io::Result<String>)>;
    let current: BTreeMap<&Path, Result<&str, String>> = match now {
        Some(now) => now
            .iter()
            .map(|(p, d)| (p.as_path(), Ok(d.as_str())))
            .collect(),
        None => {
            hashed_now = expected
                .iter()
                .map(|(p, _)| (p.clone(), file_digest(p)))
                .collect();
            hashed_now
                .iter()
                .map(|(p, d)| {
                    let d = d.as_ref().map(String::as_str).map_err(|e| e.to_string());
                    (p.as_path(), d)
                })
                .collect()
        }
    };
    let scene = pickled.display();
    for (path, then) in expected {
        let file = path.display();
        match current.get(path.as_path()) {
            Some(Ok(d)) if d == then => {}
            Some(Ok(d)) => {
                return Some(format!(
                    "{file}: changed since the scene was pickled (SHA-256 {then} then, {d} \
                     now); the pickle of {scene} refuses to load other geometry (load the \
                     file again and pickle that)"
                ));
            }
            Some(Err(e)) => {
                return Some(format!(
                    "{file}: cannot be read to unpickle the scene of {scene}: {e}"
                ));
            }
            // Read then but not now: the files that decide what is read have changed.
            None if now.is_some() => {
                return Some(format!(
                    "{file}: read when the scene of {scene} was pickled but not now: the \
                     scene has changed since the scene was pickled"
                ));
            }
            None => {}
        }
    }
    let read_then = |p: &Path| expected.iter().any(|(q, _)| q == p);
    let extra = now?.iter().find(|(p, _)| !read_then(p))?;
    Some(format!(
        "{}: read now but not when the scene of {scene} was pickled: the scene has changed \
         since the scene was pickled",
        extra.0.display()
    ))
}

impl FileSource {
    /// The pickled form (the keyword arguments of `lumis._lumis.load` plus `kind`).
    pub fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let o = &self.options;
        d.set_item("kind", "file")?;
        d.set_item("path", &self.absolute)?;
        d.set_item("defines", &self.defines)?;
        d.set_item("gltf_scene", o.scene)?;
        d.set_item("camera", o.camera)?;
        d.set_item("up", o.up.name())?;
        d.set_item("auto_camera", o.auto_camera)?;
        d.set_item("frame", o.frame)?;
        d.set_item("flatten_instances", o.flatten_instances)?;
        let files: Vec<(String, String)> = self
            .digests
            .iter()
            .map(|(p, h)| (p.to_string_lossy().into_owned(), h.clone()))
            .collect();
        d.set_item("expect_files", files)?;
        Ok(d)
    }
}

/// The pickled form of a scene built from `steps`: `{"kind": "arrays", "steps": [...]}`, each
/// step a dict of the builder's keyword arguments plus `op`, the data read back from `scene`.
pub fn arrays_state<'py>(
    py: Python<'py>,
    scene: &Scene,
    steps: &[Step],
) -> PyResult<Bound<'py, PyDict>> {
    let g = scene.geometry();
    let (mut meshes, mut spheres, mut prototypes, mut instances) = (0, 0, 0, 0);
    let list = PyList::empty(py);
    for step in steps {
        let s = PyDict::new(py);
        match step {
            Step::Mesh { name } => {
                s.set_item("op", "mesh")?;
                s.set_item("name", name)?;
                put_mesh(&s, &g.meshes()[meshes])?;
                meshes += 1;
            }
            Step::Sphere { name } => {
                let sphere = g.spheres()[spheres];
                s.set_item("op", "sphere")?;
                s.set_item("name", name)?;
                let centre = sphere.center.to_array().map(f64::from);
                s.set_item(
                    "center",
                    PyArray1::from_owned_array(py, Array1::from(centre.to_vec())),
                )?;
                s.set_item("radius", f64::from(sphere.radius))?;
                spheres += 1;
            }
            Step::Prototype => {
                s.set_item("op", "prototype")?;
                let parts = g.prototypes()[prototypes].geometry();
                put_mesh(&s, &parts.meshes()[0])?;
                prototypes += 1;
            }
            Step::Instance { prototype, name } => {
                let m = g.instances()[instances].placement.to_world();
                s.set_item("op", "instance")?;
                s.set_item("name", name)?;
                s.set_item("prototype", prototype)?;
                let rows: Vec<f64> = (0..3)
                    .flat_map(|r| {
                        let a = m.matrix3.row(r);
                        [a.x, a.y, a.z, m.translation[r]]
                    })
                    .collect();
                let rows = Array2::from_shape_vec((3, 4), rows).expect("12 entries");
                s.set_item("matrix", PyArray2::from_owned_array(py, rows))?;
                instances += 1;
            }
        }
        list.append(s)?;
    }
    let d = PyDict::new(py);
    d.set_item("kind", "arrays")?;
    d.set_item("steps", list)?;
    Ok(d)
}

/// `vertices` (float32 `(V, 3)`) and `faces` (uint32 `(F, 3)`) of `mesh` into `step`.
fn put_mesh(step: &Bound<'_, PyDict>, mesh: &lumis_core::geometry::Mesh) -> PyResult<()> {
    let py = step.py();
    let v: Vec<f32> = mesh.positions().iter().flat_map(|p| p.to_array()).collect();
    let f: Vec<u32> = mesh.indices().iter().flatten().copied().collect();
    let v = Array2::from_shape_vec((mesh.positions().len(), 3), v).expect("3 per vertex");
    let f = Array2::from_shape_vec((mesh.indices().len(), 3), f).expect("3 per face");
    step.set_item("vertices", PyArray2::from_owned_array(py, v))?;
    step.set_item("faces", PyArray2::from_owned_array(py, f))?;
    Ok(())
}
