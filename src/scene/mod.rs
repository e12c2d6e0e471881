//! The scene: geometry, the objects that own it, materials, lights, camera and render settings,
//! plus ray queries through an accelerator.
//!
//! Loaders (one per file format, in the submodules) build a `Scene` through [`SceneBuilder`];
//! [`load`] picks the loader from the file extension.

mod auto;
mod builtin;
mod error;
mod gltf;
mod mesh_m;
mod mtl;
mod obj;
mod obj_scan;
mod scn;
mod scn_camera;
mod settings;
mod toml;
mod toml_schema;

pub use auto::{UpAxis, default_rig, framing_camera};
pub use builtin::default_scene;
pub use error::SceneError;
pub use gltf::{GltfOptions, LUMENS_PER_WATT, load_gltf_bytes, load_gltf_file};
pub use mesh_m::{MeshMError, load_m_file, parse_m};
pub use obj::{ObjModel, ObjObject, load_obj, load_obj_merged, load_obj_meshes};
pub use scn::{ScnError, load_scn_file, parse_scn};
pub use settings::{
    DEFAULT_CUTOFF, MAX_DEPTH, MAX_LENS_SAMPLES, MAX_PIXELS, MAX_SIDE, MAX_SPP, Settings,
    SettingsError,
};
pub use toml::{Resolver, load_toml_file, load_toml_str};

use std::path::Path;

use crate::accel::{Accel, Hit, TraversalStats};
use crate::camera::Camera;
use crate::geometry::{Geometry, SurfacePoint};
use crate::light::Light;
use crate::material::Material;
use crate::math::Ray;

/// Loads a scene file, choosing the format by extension: `.toml` is a scene description,
/// `.scn` the paper's format, `.obj` a bare model shown with an automatic camera, a default
/// two-light rig and its MTL materials (a grey default for objects without one),
/// `.gltf`/`.glb` a glTF 2.0 scene (its default scene and first camera).
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    load_with(path, &GltfOptions::default())
}

/// [`load`] with the choices model files offer: scene and camera (glTF only), up axis and
/// automatic camera (glTF and OBJ); asking for them in any other format is an error.
pub fn load_with(path: &Path, gltf_options: &GltfOptions) -> Result<Scene, SceneError> {
    let scene = load_by_extension(path, gltf_options)?;
    // Every format's settings meet the same limits (TOML and .scn also check them where they
    // can name the element or line).
    scene
        .settings()
        .validate()
        .map_err(|e| SceneError::invalid(path, "render settings", e.to_string()))?;
    Ok(scene)
}

/// The loader of `path`'s format.
fn load_by_extension(path: &Path, gltf_options: &GltfOptions) -> Result<Scene, SceneError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("gltf" | "glb") => load_gltf_file(path, gltf_options),
        Some("obj") if gltf_options.scene.is_none() && gltf_options.camera.is_none() => {
            load_bare_obj(path, gltf_options)
        }
        _ if *gltf_options != GltfOptions::default() => Err(SceneError::invalid(
            path,
            "options",
            "a scene or camera index can only be chosen in glTF files, an up axis or the \
             automatic camera in glTF and OBJ files",
        )),
        Some("toml") => load_toml_file(path),
        Some("scn") => Ok(load_scn_file(path)?),
        _ => Err(SceneError::UnknownFormat {
            path: path.to_path_buf(),
        }),
    }
}

/// A bare OBJ file as a scene: one scene object per OBJ object, materials from its MTL files,
/// turned so that `options.up` is up (the other options are glTF's).
fn load_bare_obj(path: &Path, options: &GltfOptions) -> Result<Scene, SceneError> {
    let bytes = std::fs::read(path).map_err(|source| SceneError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let model = load_obj(&bytes, path, Some(&|p| std::fs::read(p)))?;
    let mut b = SceneBuilder::new();
    for w in model.warnings {
        b.warn(w);
    }
    let ids: Vec<u32> = model
        .materials
        .into_iter()
        .map(|m| b.add_material(m))
        .collect();
    let default = b.add_material(Material::default());
    let turn = options.up.to_y_up();
    for o in model.objects {
        let material = o.material.map_or(default, |k| ids[k]);
        let mesh = match options.up {
            UpAxis::Y => o.mesh,
            UpAxis::Z => o.mesh.transformed(&turn),
        };
        b.add_mesh(o.name, mesh, material);
    }
    let bounds = b.bounds();
    let (w, h) = (b.settings_mut().width, b.settings_mut().height);
    let camera = framing_camera(bounds, w, h);
    for light in default_rig(bounds, &camera) {
        b.add_light(light);
    }
    Ok(b.build(camera))
}

/// A named thing in the scene (a sphere or a mesh) with one material.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// Name from the scene file (or generated).
    pub name: String,
    /// Index into `Scene::materials`.
    pub material: u32,
}

/// Everything needed to render. Fields are private: `SceneBuilder` keeps the primitive →
/// object → material references valid.
#[derive(Clone, Debug)]
pub struct Scene {
    geometry: Geometry,
    prim_object: Vec<u32>,
    objects: Vec<Object>,
    materials: Vec<Material>,
    lights: Vec<Light>,
    camera: Camera,
    settings: Settings,
    warnings: Vec<String>,
}

/// A hit with its surface geometry and owning object.
#[derive(Clone, Copy, Debug)]
pub struct Interaction {
    /// Ray parameter.
    pub t: f32,
    /// Primitive index.
    pub prim: u32,
    /// Object index.
    pub object: u32,
    /// Surface geometry.
    pub surface: SurfacePoint,
}

impl Scene {
    /// The geometry.
    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }

    /// Objects, indexed by object id.
    pub fn objects(&self) -> &[Object] {
        &self.objects
    }

    /// Object owning primitive `prim`.
    pub fn object_of(&self, prim: u32) -> u32 {
        self.prim_object[prim as usize]
    }

    /// Materials.
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// Material of object `object`.
    pub fn material_of(&self, object: u32) -> &Material {
        &self.materials[self.objects[object as usize].material as usize]
    }

    /// Lights.
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// Camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// Problems the loaders survived, in the order met (each names its file).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// Render settings.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Mutable settings, for CLI overrides.
    pub fn settings_mut(&mut self) -> &mut Settings {
        &mut self.settings
    }

    /// Replaces the camera.
    pub fn set_camera(&mut self, camera: Camera) {
        self.camera = camera;
    }

    /// Nearest hit of `ray` through `accel` (built over `self.geometry().prim_bounds()`).
    pub fn intersect(
        &self,
        accel: &Accel,
        ray: &Ray,
        stats: &mut TraversalStats,
    ) -> Option<Interaction> {
        let Hit { prim, hit } = self.intersect_hit(accel, ray, stats)?;
        let mut hit_ray = *ray;
        hit_ray.t_max = hit.t;
        let object = self.object_of(prim);
        // Texture coordinates only where a texture reads them (a sphere's cost two inverse
        // trigonometric calls); elsewhere they stay 0, which nothing reads.
        let uv = self.material_of(object).reads_uv();
        Some(Interaction {
            t: hit.t,
            prim,
            object,
            surface: self.geometry.surface(prim, &hit_ray, &hit, uv),
        })
    }

    /// The nearest primitive hit of `ray`, before any surface is computed.
    pub fn intersect_hit(
        &self,
        accel: &Accel,
        ray: &Ray,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        accel.intersect_geometry(&self.geometry, self.settings.precision, ray, stats)
    }

    /// True when something blocks `ray` within `(t_min, t_max]`.
    pub fn occluded(&self, accel: &Accel, ray: &Ray, stats: &mut TraversalStats) -> bool {
        accel.occluded_geometry(&self.geometry, self.settings.precision, ray, stats)
    }
}

/// Assembles a [`Scene`], checking every reference as it goes.
#[derive(Clone, Debug)]
pub struct SceneBuilder {
    geometry: Geometry,
    prim_object: Vec<u32>,
    objects: Vec<Object>,
    materials: Vec<Material>,
    lights: Vec<Light>,
    settings: Settings,
    warnings: Vec<String>,
}

impl Default for SceneBuilder {
    fn default() -> Self {
        Self::new()
    }
}

impl SceneBuilder {
    /// An empty scene with default settings.
    pub fn new() -> Self {
        Self {
            geometry: Geometry::new(),
            prim_object: Vec::new(),
            objects: Vec::new(),
            materials: Vec::new(),
            lights: Vec::new(),
            settings: Settings::default(),
            warnings: Vec::new(),
        }
    }

    /// Adds a material; returns its index.
    pub fn add_material(&mut self, m: Material) -> u32 {
        self.materials.push(m);
        self.materials.len() as u32 - 1
    }

    /// Adds a light.
    pub fn add_light(&mut self, l: Light) {
        self.lights.push(l);
    }

    /// Number of materials so far.
    pub fn material_count(&self) -> usize {
        self.materials.len()
    }

    /// Adds a sphere object with material `material` (must exist); returns the object id.
    pub fn add_sphere(
        &mut self,
        name: impl Into<String>,
        s: crate::geometry::Sphere,
        material: u32,
    ) -> u32 {
        assert!(
            (material as usize) < self.materials.len(),
            "material {material} not added yet"
        );
        self.geometry.add_sphere(s);
        self.push_object(name.into(), material, 1)
    }

    /// Adds a mesh object with material `material` (must exist); returns the object id.
    pub fn add_mesh(
        &mut self,
        name: impl Into<String>,
        m: crate::geometry::Mesh,
        material: u32,
    ) -> u32 {
        assert!(
            (material as usize) < self.materials.len(),
            "material {material} not added yet"
        );
        let n = self.geometry.add_mesh(m).len();
        self.push_object(name.into(), material, n)
    }

    fn push_object(&mut self, name: String, material: u32, prims: usize) -> u32 {
        let id = self.objects.len() as u32;
        self.objects.push(Object { name, material });
        self.prim_object.extend(std::iter::repeat_n(id, prims));
        id
    }

    /// Settings to edit.
    pub fn settings_mut(&mut self) -> &mut Settings {
        &mut self.settings
    }

    /// Bounds of the geometry added so far (for automatic cameras).
    pub fn bounds(&self) -> crate::math::Aabb {
        self.geometry.bounds()
    }

    /// Finishes the scene with its camera.
    pub fn build(self, camera: Camera) -> Scene {
        Scene {
            geometry: self.geometry,
            prim_object: self.prim_object,
            objects: self.objects,
            materials: self.materials,
            lights: self.lights,
            camera,
            settings: self.settings,
            warnings: self.warnings,
        }
    }

    /// Records a problem the load survived (a missing texture, ignored elements); the CLI
    /// prints these before rendering.
    pub fn warn(&mut self, message: impl Into<String>) {
        self.warnings.push(message.into());
    }
}
