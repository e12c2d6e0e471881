//! [`SceneBuilder`]: the one way loaders and tests assemble a [`Scene`], so every primitive has
//! an object and every object a material.

mod singular;

use singular::PartShape;

use super::domain;
use super::limits::{self, LimitError};
use super::object_ranges::ObjectRanges;
use super::{Frame, Object, Scene, Settings};
use crate::camera::Camera;
use crate::geometry::{Geometry, Mesh, Placement, PlacementError, Sphere};
use crate::instancing::Prototype;
use crate::light::Light;
use crate::material::Material;

/// A shape of a prototype.
#[derive(Clone, Debug)]
pub enum Shape {
    /// A triangle mesh.
    Mesh(Mesh),
    /// An analytic sphere (an ellipsoid under a non-uniform placement).
    Sphere(Sphere),
}

/// One part of a prototype: a shape with its material; each instance makes an object of it.
#[derive(Clone, Debug)]
pub struct Part {
    /// Appended to the instance's name (`<instance>/<part>`) when the prototype has several.
    pub name: String,
    /// The shape, in object space.
    pub shape: Shape,
    /// Its material (added already).
    pub material: u32,
}

/// Assembles a [`Scene`], checking every reference as it goes.
#[derive(Clone, Debug)]
pub struct SceneBuilder {
    geometry: Geometry,
    object_starts: Vec<u32>,
    objects: Vec<Object>,
    materials: Vec<Material>,
    material_names: Vec<String>,
    lights: Vec<Light>,
    light_names: Vec<String>,
    /// How many of the last lights are a model file's automatic rig.
    rig_lights: usize,
    settings: Settings,
    warnings: Vec<String>,
    /// The parts of each prototype: object name suffix, material and shape.
    prototype_parts: Vec<Vec<(String, u32, PartShape)>>,
    /// The first primitive of each part, by prototype.
    prototype_starts: Vec<Vec<u32>>,
    instance_objects: Vec<u32>,
    /// The first element outside [`limits`], reported by [`SceneBuilder::build`]: loaders
    /// keep their simple add calls, and no format can add an element unchecked.
    rejected: Option<LimitError>,
    frame: Option<Frame>,
    /// Triangles singular placements may still copy ([`singular`]).
    singular_budget: usize,
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
            object_starts: Vec::new(),
            objects: Vec::new(),
            materials: Vec::new(),
            material_names: Vec::new(),
            lights: Vec::new(),
            light_names: Vec::new(),
            rig_lights: 0,
            prototype_parts: Vec::new(),
            prototype_starts: Vec::new(),
            instance_objects: Vec::new(),
            settings: Settings::default(),
            warnings: Vec::new(),
            rejected: None,
            frame: None,
            singular_budget: singular::MAX_SINGULAR_TRIANGLES,
        }
    }

    /// Records `result` of checking `element` (the first failure wins).
    fn check(&mut self, element: impl FnOnce() -> String, result: Result<(), String>) {
        if let (Err(message), None) = (result, &self.rejected) {
            self.rejected = Some(LimitError {
                element: element(),
                message,
            });
        }
    }

    /// Adds a material named `material<index>`; returns its index.
    pub fn add_material(&mut self, m: Material) -> u32 {
        let name = format!("material{}", self.materials.len());
        self.add_named_material(name, m)
    }

    /// Adds a material with the name the scene file gives it (what Cryptomatte's
    /// `CryptoMaterial` mattes are called); returns its index.
    pub fn add_named_material(&mut self, name: impl Into<String>, m: Material) -> u32 {
        let name = name.into();
        self.check(
            || format!("material \"{name}\""),
            limits::check_material(&m),
        );
        self.materials.push(m);
        self.material_names.push(name);
        self.materials.len() as u32 - 1
    }

    /// Adds a light named `light<index>`.
    pub fn add_light(&mut self, l: Light) {
        let name = format!("light{}", self.lights.len());
        self.add_named_light(&name, l);
    }

    /// Adds a light of the automatic rig a model file without lights gets (`rig_key`,
    /// `rig_fill`, ...): the lights an environment replaces ([`Scene::set_environment`]).
    /// They must be the last lights added.
    pub fn add_rig_light(&mut self, l: Light) {
        let name = format!("rig{}", self.rig_lights);
        self.add_named_light(&name, l);
        self.rig_lights += 1;
    }

    /// Adds a light with the name the scene file gives it (what its per-light pass is
    /// called), made unique and EXR-safe by [`unique_light_name`].
    pub fn add_named_light(&mut self, name: &str, l: Light) {
        let n = self.lights.len();
        self.check(|| format!("light[{n}]"), limits::check_light(&l));
        let name = unique_light_name(&self.light_names, name);
        self.lights.push(l);
        self.light_names.push(name);
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
        let name = self.checked_shape("sphere", name.into(), material, &s.bounds());
        self.geometry.add_sphere(s);
        self.push_object(name, material, 1)
    }

    /// Adds a mesh object with material `material` (must exist); returns the object id.
    pub fn add_mesh(
        &mut self,
        name: impl Into<String>,
        m: crate::geometry::Mesh,
        material: u32,
    ) -> u32 {
        let name = self.checked_shape("mesh", name.into(), material, &m.bounds());
        let n = self.geometry.add_mesh(m).len();
        self.push_object(name, material, n)
    }

    /// Checks a `kind` object's material (must exist) and bounds (within the limits) before
    /// it is added; returns its name.
    fn checked_shape(
        &mut self,
        kind: &str,
        name: String,
        material: u32,
        bounds: &crate::math::Aabb,
    ) -> String {
        self.assert_material(material);
        self.check(
            || format!("{kind} \"{name}\""),
            limits::check_bounds(bounds),
        );
        name
    }

    /// Panics unless material `material` was added: loaders add materials before what uses
    /// them, so a miss is a bug in the loader, not in its file.
    fn assert_material(&self, material: u32) {
        assert!(
            (material as usize) < self.materials.len(),
            "material {material} not added yet"
        );
    }

    /// Adds a prototype made of `parts` (a name, a shape and a material each, the materials
    /// added already), which instances place ([`SceneBuilder::add_instance`]); returns its
    /// index. Its hierarchy is built here, once, however many instances place it.
    pub fn add_prototype(&mut self, parts: Vec<Part>) -> u32 {
        let mut g = Geometry::new();
        let mut starts = Vec::with_capacity(parts.len());
        let mut names = Vec::with_capacity(parts.len());
        for part in parts {
            self.assert_material(part.material);
            starts.push(g.prims().len() as u32);
            let (bounds, shape) = match part.shape {
                Shape::Mesh(m) => {
                    let b = m.bounds();
                    let mesh = g.meshes().len() as u32;
                    g.add_mesh(m);
                    (b, PartShape::Mesh(mesh))
                }
                Shape::Sphere(s) => {
                    let b = s.bounds();
                    g.add_sphere(s);
                    (b, PartShape::Sphere)
                }
            };
            let name = part.name;
            self.check(
                || format!("prototype part \"{name}\""),
                limits::check_bounds(&bounds),
            );
            names.push((name, part.material, shape));
        }
        self.prototype_parts.push(names);
        self.prototype_starts.push(starts);
        self.geometry.add_prototype(Prototype::shared(g))
    }

    /// Places prototype `prototype` (must exist) by `to_world` as instance `name`: one object
    /// per part of the prototype, named `name` (one part) or `name/<part>`. Returns the first
    /// object's id. A singular transform (a zero scale: glTF allows it, to hide a node) has no
    /// inverse to move rays by: its parts are drawn as flattened copies instead, with the same
    /// objects and no instance ([`singular`]). A non-finite transform, or a placement outside
    /// the value limits, is reported by [`SceneBuilder::build`].
    pub fn add_instance(
        &mut self,
        prototype: u32,
        name: impl Into<String>,
        to_world: glam::DAffine3,
    ) -> u32 {
        let name = name.into();
        let placement = match Placement::new(to_world) {
            Ok(p) => p,
            Err(PlacementError::Singular { .. }) => {
                return self.add_singular_placement(prototype, &name, to_world);
            }
            Err(e) => {
                self.check(|| format!("instance \"{name}\""), Err(e.to_string()));
                // Recorded: the scene is refused at `build`; the identity keeps ids going.
                Placement::new(glam::DAffine3::IDENTITY).expect("the identity is invertible")
            }
        };
        let prim = self.geometry.add_instance(prototype, placement);
        let bounds = self.geometry.instances()[self.geometry.instances().len() - 1].bounds;
        self.check(
            || format!("instance \"{name}\""),
            limits::check_bounds(&bounds),
        );
        let first = self.objects.len() as u32;
        self.instance_objects.push(first);
        for (object, material, _) in self.part_objects(prototype, &name) {
            self.objects.push(Object {
                name: object,
                material,
            });
            // Every part object starts at the instance's primitive (`Scene::object_at` finds
            // them through the instance; the next primitive's object starts after it).
            self.object_starts.push(prim);
        }
        first
    }

    /// The objects a placement `name` of prototype `prototype` makes, one per part: name
    /// (`name` for one part, `name/<part>` for several), material and shape.
    fn part_objects(&self, prototype: u32, name: &str) -> Vec<(String, u32, PartShape)> {
        let parts = &self.prototype_parts[prototype as usize];
        let object = |part: &str| match parts.len() {
            1 => name.to_string(),
            _ => format!("{name}/{part}"),
        };
        parts
            .iter()
            .map(|(part, material, shape)| (object(part), *material, *shape))
            .collect()
    }

    /// Number of instances so far.
    pub fn instance_count(&self) -> usize {
        self.geometry.instances().len()
    }

    fn push_object(&mut self, name: String, material: u32, prims: usize) -> u32 {
        let id = self.objects.len() as u32;
        self.objects.push(Object { name, material });
        // Objects own consecutive primitives, added in order: the first of each is enough.
        self.object_starts
            .push((self.geometry.prims().len() - prims) as u32);
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

    /// Finishes the scene with its camera, or names the first element (in the order added)
    /// outside the value limits of [`limits`]: too far, too large or too bright to render
    /// without overflow.
    pub fn build(mut self, camera: Camera) -> Result<Scene, LimitError> {
        self.check(|| "camera".into(), domain::check_camera(&camera));
        if let Some(e) = self.rejected {
            return Err(e);
        }
        let object_ranges = ObjectRanges::new(self.object_starts, self.geometry.prims().len());
        Ok(Scene {
            geometry: self.geometry,
            instance_objects: self.instance_objects,
            prototype_parts: self.prototype_starts,
            object_ranges,
            objects: self.objects,
            materials: self.materials,
            material_names: self.material_names,
            lights: self.lights,
            light_names: self.light_names,
            rig_lights: self.rig_lights,
            camera,
            settings: self.settings,
            warnings: self.warnings,
            frame: self.frame,
            environment: None,
            sun_light: false,
        })
    }

    /// Marks the scene as frame `frame` of an animation (the loader has posed it there).
    pub fn set_frame(&mut self, frame: Frame) {
        self.frame = Some(frame);
    }

    /// Records a problem the load survived (a missing texture, ignored elements); the CLI
    /// prints these before rendering.
    pub fn warn(&mut self, message: impl Into<String>) {
        self.warnings.push(message.into());
    }
}

/// `name` as a light name: every character other than a letter, digit, `_` or `-` becomes
/// `_` (an EXR layer name must not gain dots), an empty name becomes `light`, and a name
/// already in `taken` gets the first free suffix `_2`, `_3`, ...
pub fn unique_light_name(taken: &[String], name: &str) -> String {
    let clean: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let clean = if clean.is_empty() {
        "light".to_string()
    } else {
        clean
    };
    let free = |n: &str| !taken.iter().any(|t| t == n);
    if free(&clean) {
        return clean;
    }
    (2..)
        .map(|k| format!("{clean}_{k}"))
        .find(|n| free(n))
        .expect("a free suffix")
}

#[cfg(test)]
mod tests;
