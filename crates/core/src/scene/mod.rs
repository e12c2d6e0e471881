//! The scene model: geometry, the objects that own it, materials, lights, camera and render
//! settings; [`World`] pairs a scene with the accelerator built over it for ray queries.
//!
//! File formats live in [`crate::formats`]; each builds a `Scene` through [`SceneBuilder`].
//! A scene is a still; an animated one is posed at one frame by its loader ([`animation`]).

mod all_hits;
pub mod animation;
mod auto;
mod builder;
mod contains;
pub mod domain;
pub mod limits;
mod object_ranges;
mod settings;
mod world;

pub use all_hits::{AllHitsBuffers, SurfaceHit};
pub use animation::{Frame, FrameRate};
pub use auto::{UpAxis, default_rig, framing_camera};
pub use builder::{Part, SceneBuilder, Shape};
pub use contains::{Containment, ContainmentMethod, PointError, check_points};
pub use limits::LimitError;
pub use settings::{
    DEFAULT_CUTOFF, MAX_DEPTH, MAX_LENS_SAMPLES, MAX_PIXELS, MAX_SIDE, MAX_SPP, Settings,
    SettingsError, check_adaptive,
};
pub use world::World;

use std::sync::Arc;

use crate::camera::Camera;
use crate::environment::Environment;
use crate::geometry::{Geometry, SurfacePoint};
use crate::light::Light;
use crate::material::Material;
use object_ranges::ObjectRanges;

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
    /// The first object of each instance (one per part of its prototype, in part order).
    instance_objects: Vec<u32>,
    /// The first primitive of each part of each prototype, by prototype.
    prototype_parts: Vec<Vec<u32>>,
    /// The primitives of each object.
    object_ranges: ObjectRanges,
    objects: Vec<Object>,
    materials: Vec<Material>,
    material_names: Vec<String>,
    lights: Vec<Light>,
    /// Light names, by light index (the scene file's, else `light<index>`).
    light_names: Vec<String>,
    /// How many of the last lights (before an environment's sun) are a model file's
    /// automatic rig, which an environment replaces.
    rig_lights: usize,
    camera: Camera,
    settings: Settings,
    warnings: Vec<String>,
    frame: Option<Frame>,
    /// The world around the scene, if any (`--env`, `[environment]`); shared, since a map
    /// and its irradiance table are large and animation frames reuse them.
    environment: Option<Arc<Environment>>,
    /// Whether the last light is the environment's sun (replaced with the environment).
    sun_light: bool,
}

/// A hit with its surface geometry and owning object.
#[derive(Clone, Copy, Debug)]
pub struct Interaction {
    /// Ray parameter.
    pub t: f32,
    /// Primitive index (in the scene's primitive list: an instance's, for a hit on one).
    pub prim: u32,
    /// The prototype's primitive, for a hit on an instance (0 otherwise).
    pub inner: u32,
    /// The instance hit, if the primitive is one.
    pub instance: Option<u32>,
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

    /// The geometry, for building its instances' hierarchies ([`World::build`]).
    pub(crate) fn geometry_mut(&mut self) -> &mut Geometry {
        &mut self.geometry
    }

    /// Objects, indexed by object id.
    pub fn objects(&self) -> &[Object] {
        &self.objects
    }

    /// Object owning primitive `prim`.
    #[inline]
    pub fn object_of(&self, prim: u32) -> u32 {
        self.object_ranges.object_of(prim)
    }

    /// Object owning a hit on primitive `prim` with [`crate::geometry::PrimHit::inner`]
    /// `inner`: for an instance, its object for the prototype's part holding `inner`.
    #[inline]
    pub fn object_at(&self, prim: u32, inner: u32) -> u32 {
        match self
            .geometry
            .has_instances()
            .then(|| self.geometry.instance_of(prim))
        {
            Some(Some(instance)) => self.instance_object(instance, inner),
            _ => self.object_of(prim),
        }
    }

    /// The object of instance `instance` for its prototype's primitive `inner`.
    #[inline]
    pub fn instance_object(&self, instance: u32, inner: u32) -> u32 {
        let proto = self.geometry.instances()[instance as usize].prototype;
        let starts = &self.prototype_parts[proto as usize];
        // A prototype of one part (most are) needs no search: per-hit records ask this.
        let part = match starts.len() {
            1 => 0,
            _ => starts.partition_point(|&s| s <= inner) - 1,
        };
        self.instance_objects[instance as usize] + part as u32
    }

    /// The first object of each instance (see [`Scene::instance_object`]).
    pub fn instance_objects(&self) -> &[u32] {
        &self.instance_objects
    }

    /// Materials.
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// Material names, by material index (the scene file's, else `material<index>`).
    pub fn material_names(&self) -> &[String] {
        &self.material_names
    }

    /// Material of object `object`.
    pub fn material_of(&self, object: u32) -> &Material {
        &self.materials[self.objects[object as usize].material as usize]
    }

    /// Lights.
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// Light names, by light index: unique, and made of letters, digits, `_` and `-` only, so
    /// that they can name EXR layers (`light.<name>.R`).
    pub fn light_names(&self) -> &[String] {
        &self.light_names
    }

    /// The environment around the scene, if any.
    pub fn environment(&self) -> Option<&Environment> {
        self.environment.as_deref()
    }

    /// Sets (or removes) the environment. Its sun, when it has one, becomes the last light,
    /// named `sun`; a previous environment's sun light goes with it. An environment replaces
    /// the automatic light rig of a model file without lights, as glTF viewers light such a
    /// model by its environment alone (the file's own lights stay).
    pub fn set_environment(&mut self, environment: Option<Arc<Environment>>) {
        if self.sun_light {
            self.lights.pop();
            self.light_names.pop();
            self.sun_light = false;
        }
        if environment.is_some() && self.rig_lights > 0 {
            let keep = self.lights.len() - self.rig_lights;
            self.lights.truncate(keep);
            self.light_names.truncate(keep);
            self.rig_lights = 0;
        }
        if let Some(sun) = environment.as_ref().and_then(|e| e.sun_light()) {
            let name = builder::unique_light_name(&self.light_names, "sun");
            self.lights.push(sun);
            self.light_names.push(name);
            self.sun_light = true;
        }
        self.environment = environment;
    }

    /// Records a problem the caller survived (a clamped environment texel, ...).
    pub fn warn(&mut self, message: impl Into<String>) {
        self.warnings.push(message.into());
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

    /// The frame of its animation the scene was posed at; `None` for a still.
    pub fn frame(&self) -> Option<Frame> {
        self.frame
    }

    /// Replaces the camera.
    pub fn set_camera(&mut self, camera: Camera) {
        self.camera = camera;
    }
}
