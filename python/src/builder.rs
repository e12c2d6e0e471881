//! `lumis._lumis.SceneBuilder`: a scene from numpy arrays through lumis-core's
//! [`SceneBuilder`], the one the file loaders use (same meshes, same hierarchy, same answers).
//! Each add returns the id the queries report; the steps are kept (without their data, which
//! the scene holds) so that the scene can be pickled and rebuilt ([`crate::source`]).

use lumis_core::geometry::{Mesh, Sphere};
use lumis_core::material::Material;
use lumis_core::scene::{Part, SceneBuilder, Shape, default_rig, framing_camera};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

use crate::arrays;
use crate::scene::PyScene;
use crate::source::{Source, Step};

/// The builder of a scene from arrays (see `lumis.SceneBuilder`).
#[pyclass(name = "SceneBuilder", module = "lumis._lumis")]
pub struct PySceneBuilder {
    /// `None` once built.
    builder: Option<SceneBuilder>,
    /// The one material every shape gets (lumis's default grey, as an OBJ without MTL).
    material: u32,
    steps: Vec<Step>,
    objects: u32,
    primitives: u64,
    prototypes: u32,
    instances: u32,
}

impl PySceneBuilder {
    fn builder(&mut self) -> PyResult<&mut SceneBuilder> {
        self.builder.as_mut().ok_or_else(|| {
            PyRuntimeError::new_err(
                "this SceneBuilder has been built (or its build failed); start a new one",
            )
        })
    }

    /// Reserves `count` primitive ids, refusing a scene past the u32 ids the queries report.
    fn reserve(&mut self, count: usize) -> PyResult<()> {
        let total = self.primitives + count as u64;
        if total > u64::from(u32::MAX) {
            return Err(PyValueError::new_err(format!(
                "the scene would have {total} primitives; at most {} fit the ids",
                u32::MAX
            )));
        }
        self.primitives = total;
        Ok(())
    }

    /// The mesh of `vertices` and `faces`, checked row by row.
    fn mesh(vertices: &Bound<'_, PyAny>, faces: &Bound<'_, PyAny>) -> PyResult<Mesh> {
        let positions = arrays::vertices(vertices, "vertices")?;
        let indices = arrays::faces(faces, "faces", positions.len())?;
        // The arrays were checked above; the core checks the same again and names the first.
        Mesh::new(positions, None, None, indices).map_err(|e| PyValueError::new_err(e.to_string()))
    }
}

#[pymethods]
impl PySceneBuilder {
    #[new]
    fn new() -> Self {
        let mut builder = SceneBuilder::new();
        let material = builder.add_named_material("default", Material::default());
        Self {
            builder: Some(builder),
            material,
            steps: Vec::new(),
            objects: 0,
            primitives: 0,
            prototypes: 0,
            instances: 0,
        }
    }

    /// Adds a mesh object; returns `(obj_id, first_prim)`: its triangles are primitives
    /// `first_prim + row`.
    #[pyo3(signature = (*, vertices, faces, name=None))]
    fn add_mesh(
        &mut self,
        vertices: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
        name: Option<String>,
    ) -> PyResult<(u32, u64)> {
        self.builder()?;
        let mesh = Self::mesh(vertices, faces)?;
        let first = self.primitives;
        self.reserve(mesh.triangle_count())?;
        let id = self.objects;
        let name = name.unwrap_or_else(|| format!("mesh{id}"));
        let material = self.material;
        self.builder()?.add_mesh(name.clone(), mesh, material);
        self.steps.push(Step::Mesh { name });
        self.objects += 1;
        Ok((id, first))
    }

    /// Adds a sphere object; returns `(obj_id, prim_id)`.
    #[pyo3(signature = (*, center, radius, name=None))]
    fn add_sphere(
        &mut self,
        center: &Bound<'_, PyAny>,
        radius: f64,
        name: Option<String>,
    ) -> PyResult<(u32, u64)> {
        self.builder()?;
        let sphere = Sphere {
            center: arrays::centre(center)?,
            radius: arrays::radius(radius)?,
        };
        let prim = self.primitives;
        self.reserve(1)?;
        let id = self.objects;
        let name = name.unwrap_or_else(|| format!("sphere{id}"));
        let material = self.material;
        self.builder()?.add_sphere(name.clone(), sphere, material);
        self.steps.push(Step::Sphere { name });
        self.objects += 1;
        Ok((id, prim))
    }

    /// Adds a prototype (a mesh that instances place; its hierarchy is built here, once,
    /// without the GIL); returns its index.
    #[pyo3(signature = (*, vertices, faces))]
    fn add_prototype(
        &mut self,
        py: Python<'_>,
        vertices: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
    ) -> PyResult<u32> {
        self.builder()?;
        let mesh = Self::mesh(vertices, faces)?;
        let part = Part {
            name: String::new(),
            shape: Shape::Mesh(mesh),
            material: self.material,
        };
        let builder = self.builder()?;
        let index = py.detach(|| builder.add_prototype(vec![part]));
        self.steps.push(Step::Prototype);
        self.prototypes += 1;
        Ok(index)
    }

    /// Places prototype `prototype` by `matrix`; returns `(inst_id, obj_id)`.
    #[pyo3(signature = (*, prototype, matrix, name=None))]
    fn add_instance(
        &mut self,
        prototype: u32,
        matrix: &Bound<'_, PyAny>,
        name: Option<String>,
    ) -> PyResult<(u32, u32)> {
        self.builder()?;
        if prototype >= self.prototypes {
            return Err(PyValueError::new_err(format!(
                "prototype {prototype}: this builder has {} prototypes",
                self.prototypes
            )));
        }
        let to_world = arrays::placement(matrix)?;
        self.reserve(1)?;
        let id = self.instances;
        let name = name.unwrap_or_else(|| format!("instance{id}"));
        let object = self
            .builder()?
            .add_instance(prototype, name.clone(), to_world);
        self.steps.push(Step::Instance { prototype, name });
        self.instances += 1;
        self.objects += 1;
        Ok((id, object))
    }

    /// The scene: lumis's default material on every shape, the automatic framing camera and
    /// light rig of a model file (so that it renders as an OBJ would). A shape outside the
    /// coordinate limits is refused here, by name.
    fn build(&mut self, py: Python<'_>) -> PyResult<PyScene> {
        self.builder()?;
        let mut builder = self.builder.take().expect("checked above");
        let bounds = builder.bounds();
        let settings = builder.settings_mut();
        let camera = framing_camera(bounds, settings.width, settings.height);
        for light in default_rig(bounds, &camera) {
            builder.add_rig_light(light);
        }
        let scene = py
            .detach(|| builder.build(camera))
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(PyScene::new(
            scene,
            Source::Arrays(std::mem::take(&mut self.steps)),
        ))
    }
}
