//! `lumis._lumis.Scene`: a loaded scene and the accelerators built over it on demand, one per
//! (accelerator, precision) asked for, each built once and shared by every later query
//! (queries from several Python threads run concurrently, without the GIL).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};

use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::batch::{check_rays, sphere_rows, trace_all_hits_parts, trace_rays, triangle_rows};
use lumis_core::geometry::{Precision, Primitive};
use lumis_core::scene::{Scene, World};
use lumis_io::request::SettingsFlags;
use numpy::ndarray::Array2;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::choices;
use crate::errors::RayError;
use crate::hits::{AllHitColumns, HitColumns, blocked};
use crate::rays::RayArgs;
use crate::source::{self, Source};
use crate::threads;

/// Whether this build has the all-hits query ([`PyScene::intersect_all`]).
pub const ALL_HITS_AVAILABLE: bool = true;

type WorldKey = (AccelKind, Precision);

/// A scene loaded by `lumis.load` or built from arrays (`lumis.SceneBuilder`).
#[pyclass(name = "Scene", module = "lumis._lumis", frozen)]
pub struct PyScene {
    scene: Scene,
    source: Source,
    worlds: Mutex<HashMap<WorldKey, Arc<OnceLock<Arc<World>>>>>,
}

impl PyScene {
    /// Wraps a scene from `source`.
    pub fn new(scene: Scene, source: Source) -> Self {
        Self {
            scene,
            source,
            worlds: Mutex::new(HashMap::new()),
        }
    }

    /// The file the scene was loaded from (as given), `None` for a scene from arrays.
    /// Where a scene loaded from a file came from; `None` for one built from arrays.
    pub fn file_source(&self) -> Option<&source::FileSource> {
        match &self.source {
            Source::File(f) => Some(f),
            Source::Arrays(_) => None,
        }
    }

    pub fn file(&self) -> Option<&Path> {
        match &self.source {
            Source::File(f) => Some(&f.given),
            Source::Arrays(_) => None,
        }
    }

    /// The loaded scene (settings as the file and the overrides left them).
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The world for `key`, built on first use (on the current rayon pool, without the GIL).
    pub fn world(&self, key: WorldKey) -> Arc<World> {
        let cell = {
            let mut worlds = self.worlds.lock().unwrap_or_else(|p| p.into_inner());
            worlds.entry(key).or_default().clone()
        };
        cell.get_or_init(|| {
            let (kind, precision) = key;
            let mut scene = self.scene.clone();
            scene.settings_mut().precision = precision;
            let options = BuildOptions {
                max_leaf_size: kind.default_leaf_size(),
                ..Default::default()
            };
            Arc::new(World::build(scene, kind, &options))
        })
        .clone()
    }

    /// The world key of the `accel` and `precision` arguments.
    fn key(&self, accel: &str, precision: Option<&str>) -> PyResult<WorldKey> {
        let kind = choices::accel(accel)?;
        let precision = match precision {
            None => self.scene.settings().precision,
            Some(p) => choices::precision(p)?,
        };
        Ok((kind, precision))
    }

    /// Checks and traces the rays of `args` (nearest or any hit) without the GIL.
    fn query(
        &self,
        py: Python<'_>,
        args: &RayArgs<'_>,
        key: WorldKey,
        threads: Option<usize>,
        any_hit: bool,
    ) -> PyResult<Vec<lumis_core::batch::HitRecord>> {
        let rays = args.rays();
        let traced = py.detach(|| {
            threads::run(threads, || {
                check_rays(&rays)?;
                let world = self.world(key);
                Ok(trace_rays(&world, &rays, any_hit))
            })
        })?;
        traced.map_err(|(i, e)| RayError::new_err(format!("ray {i}: {e}")))
    }
}

#[pymethods]
impl PyScene {
    /// The file the scene was loaded from, as given; `None` for a scene from arrays.
    #[getter]
    fn path(&self) -> Option<PathBuf> {
        self.file().map(Path::to_path_buf)
    }

    /// What the scene pickles as: a dict with `kind` `"file"` (the keyword arguments of
    /// `load` that reload it, the SHA-256 of each file read among them) or `"arrays"` (the
    /// builder's steps with their arrays).
    fn pickle_state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        match &self.source {
            Source::File(f) => f.state(py),
            Source::Arrays(steps) => source::arrays_state(py, &self.scene, steps),
        }
    }

    /// The `prim_id` of each object's first primitive, as the queries report it (int64,
    /// one per object; -1 for an object without primitives): a mesh object's face `row` is
    /// primitive `first_prim + row`. An instance's objects count from its prototype's
    /// primitives (as `prim_id` does on an instance).
    #[getter]
    fn first_prim<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        numpy::IntoPyArray::into_pyarray(first_prims(&self.scene), py)
    }

    /// Primitives (spheres and triangles), in id order.
    #[getter]
    fn num_primitives(&self) -> usize {
        self.scene.geometry().prims().len()
    }

    /// Objects (what `obj_id` counts).
    #[getter]
    fn num_objects(&self) -> usize {
        self.scene.objects().len()
    }

    /// The render settings a dict: width, height, spp (per axis), max_depth, exposure,
    /// precision.
    #[getter]
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let st = self.scene.settings();
        let d = PyDict::new(py);
        d.set_item("width", st.width)?;
        d.set_item("height", st.height)?;
        d.set_item("spp", st.spp)?;
        d.set_item("max_depth", st.max_depth)?;
        d.set_item("exposure", st.exposure)?;
        d.set_item("precision", st.precision.name())?;
        Ok(d)
    }

    /// Warnings the loader gave (what `lumis render` prints as `warning: ...`).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.scene.warnings().to_vec()
    }

    /// Every triangle as float32 `(M, 10)`: primitive id, then the three world-space vertices
    /// (what `lumis hits --triangles-out` writes).
    fn triangles<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        rows_array(py, triangle_rows(&self.scene))
    }

    /// Every sphere as float32 `(K, 5)`: primitive id, world-space centre xyz, radius (what
    /// `lumis hits --spheres-out` writes).
    fn spheres<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        rows_array(py, sphere_rows(&self.scene))
    }

    /// Nearest hits: a dict of numpy arrays `t, prim_id, obj_id, u, v, normal, kind`.
    #[pyo3(signature = (origins, directions, t_min, t_max, *, precision=None, accel="sah", threads=None))]
    #[allow(clippy::too_many_arguments)]
    fn intersect<'py>(
        &self,
        py: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        t_min: &Bound<'py, PyAny>,
        t_max: &Bound<'py, PyAny>,
        precision: Option<&str>,
        accel: &str,
        threads: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let key = self.key(accel, precision)?;
        let args = RayArgs::extract(origins, directions, t_min, t_max)?;
        let records = self.query(py, &args, key, threads, false)?;
        let columns = py.detach(|| threads::run(threads, || HitColumns::new(&records)))?;
        columns.into_dict(py)
    }

    /// Any-hit queries: a bool array, true where something blocks the ray.
    #[pyo3(signature = (origins, directions, t_min, t_max, *, precision=None, accel="sah", threads=None))]
    #[allow(clippy::too_many_arguments)]
    fn occluded<'py>(
        &self,
        py: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        t_min: &Bound<'py, PyAny>,
        t_max: &Bound<'py, PyAny>,
        precision: Option<&str>,
        accel: &str,
        threads: Option<usize>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let key = self.key(accel, precision)?;
        let args = RayArgs::extract(origins, directions, t_min, t_max)?;
        let records = self.query(py, &args, key, threads, true)?;
        Ok(blocked(py, &records))
    }

    /// All hits along each ray ([`trace_all_hits_parts`], the function of `lumis hits --all`): the
    /// per-hit columns of [`HitColumns`] plus `ray` (int64 ray index) and `graze` (bool).
    #[pyo3(signature = (origins, directions, t_min, t_max, *, precision=None, accel="sah", threads=None))]
    #[allow(clippy::too_many_arguments)]
    fn intersect_all<'py>(
        &self,
        py: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        t_min: &Bound<'py, PyAny>,
        t_max: &Bound<'py, PyAny>,
        precision: Option<&str>,
        accel: &str,
        threads: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let key = self.key(accel, precision)?;
        let args = RayArgs::extract(origins, directions, t_min, t_max)?;
        let rays = args.rays();
        let traced = py.detach(|| {
            threads::run(threads, || {
                check_rays(&rays)?;
                let world = self.world(key);
                Ok(AllHitColumns::new(&trace_all_hits_parts(&world, &rays)))
            })
        })?;
        let columns = traced.map_err(|(i, e)| RayError::new_err(format!("ray {i}: {e}")))?;
        columns.into_dict(py)
    }

    /// Renders the scene (see `lumis.Scene.render` for the arguments): a dict with the EXR's
    /// channels, the exposure applied and whether it was automatic.
    #[pyo3(signature = (*, width=None, height=None, spp=None, max_depth=None, aovs=Vec::new(), seed=0, threads=None, exposure=None, accel="sah", precision=None, transparent=false, float_rgba=false, layout="lumis", tonemap="none", display=None, paths=Vec::new(), display_server=None))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        width: Option<u32>,
        height: Option<u32>,
        spp: Option<u32>,
        max_depth: Option<u32>,
        aovs: Vec<String>,
        seed: u64,
        threads: Option<usize>,
        exposure: Option<f32>,
        accel: &str,
        precision: Option<&str>,
        transparent: bool,
        float_rgba: bool,
        layout: &str,
        tonemap: &str,
        display: Option<&str>,
        paths: Vec<PathBuf>,
        display_server: Option<&str>,
    ) -> PyResult<Bound<'py, PyDict>> {
        // Checked in this order, so the first bad name is the one reported.
        let aovs = choices::aovs(&aovs)?;
        let layout = choices::layout(layout)?;
        let tonemap = choices::tonemap(tonemap)?;
        let display = choices::display(display)?;
        let accel = choices::accel(accel)?;
        let precision = precision.map(choices::precision).transpose()?;
        let display_server = display_server
            .map(|s| {
                lumis_io::display::DisplayServer::parse(s)
                    .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))
            })
            .transpose()?;
        let request = crate::render::Request {
            settings: SettingsFlags {
                width,
                height,
                spp,
                max_depth,
                precision,
                display,
            },
            aovs,
            seed,
            threads,
            exposure,
            accel,
            transparent,
            float_rgba,
            layout,
            tonemap,
            paths,
            display_server,
        };
        crate::render::render(py, self, &request)
    }
}

/// See [`PyScene::first_prim`]. Each prototype's parts are found once (from its first
/// instance), however many instances place it.
fn first_prims(scene: &Scene) -> Vec<i64> {
    let g = scene.geometry();
    let mut first = vec![-1i64; scene.objects().len()];
    let mut claim = |object: u32, prim: u32| {
        let slot = &mut first[object as usize];
        if *slot < 0 {
            *slot = i64::from(prim);
        }
    };
    // By prototype: (part, first primitive of the part) for each part.
    let mut parts: HashMap<u32, Vec<(u32, u32)>> = HashMap::new();
    for (p, prim) in g.prims().iter().enumerate() {
        let Primitive::Instance { instance } = *prim else {
            claim(scene.object_of(p as u32), p as u32);
            continue;
        };
        let proto = g.instances()[instance as usize].prototype;
        let base = scene.instance_objects()[instance as usize];
        let starts = parts.entry(proto).or_insert_with(|| {
            let count = g.prototypes()[proto as usize].geometry().prims().len() as u32;
            let mut starts: Vec<(u32, u32)> = Vec::new();
            for inner in 0..count {
                let part = scene.instance_object(instance, inner) - base;
                if starts.last().is_none_or(|&(last, _)| last != part) {
                    starts.push((part, inner));
                }
            }
            starts
        });
        for &(part, start) in starts.iter() {
            claim(base + part, start);
        }
    }
    first
}

/// `rows` as a float32 `(len, N)` array.
fn rows_array<const N: usize>(py: Python<'_>, rows: Vec<[f32; N]>) -> Bound<'_, PyArray2<f32>> {
    let n = rows.len();
    let flat: Vec<f32> = rows.into_iter().flatten().collect();
    PyArray2::from_owned_array(py, Array2::from_shape_vec((n, N), flat).expect("N per row"))
}
