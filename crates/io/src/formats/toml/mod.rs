//! The TOML scene format (documented in `docs/scene-format.md`): parsing into the schema of
//! [`schema`], then checking every value and reference while building the [`Scene`].

mod animation;
mod environment;
mod instance;
mod mesh;
mod overrides;
mod render;
mod schema;

pub use instance::MAX_INSTANCE_OBJECTS;
pub(crate) use overrides::refuse_non_render;
pub use overrides::{Override, apply_render_overrides};

use std::collections::{HashMap, HashSet};
use std::path::Path;

use super::{Resolver, SceneError, read_file_bytes, read_text};
use animation::Animation;
use instance::Target;
use lumis_core::camera::Camera;
use lumis_core::geometry::Sphere;
use lumis_core::light::Light;
use lumis_core::material::{Material, Texture};
use lumis_core::math::Vec3;
use lumis_core::scene::Scene;
use lumis_core::scene::{Part, SceneBuilder, Shape, domain, framing_camera};
use schema::{CameraDoc, LightDoc, LightKind, MaterialDoc, RenderDoc, SceneDoc};

/// Loads the TOML scene at `path`; referenced files are read from disk relative to its folder.
pub fn load_toml_file(path: &Path) -> Result<Scene, SceneError> {
    load_toml_file_with(path, &[])
}

/// [`load_toml_file`] with `-D` overrides applied to the document before it is checked.
pub fn load_toml_file_with(path: &Path, overrides: &[Override]) -> Result<Scene, SceneError> {
    load_toml_file_at(path, overrides, None)
}

/// [`load_toml_file_with`] posed at `frame` of the scene's `[animation]` (`--frame`; `None`:
/// frame 0 of an animated scene). A frame outside the animation, or any frame of a scene
/// without one, is an error.
pub fn load_toml_file_at(
    path: &Path,
    overrides: &[Override],
    frame: Option<u32>,
) -> Result<Scene, SceneError> {
    let text = read_text(path)?;
    load_toml_str_at(&text, path, &read_file_bytes, overrides, frame)
}

/// Loads a TOML scene from `text`. `origin` is the scene's path: it names the file in errors and
/// its folder is where relative mesh paths start. `resolver` reads referenced files.
pub fn load_toml_str(
    text: &str,
    origin: &Path,
    resolver: Resolver<'_>,
) -> Result<Scene, SceneError> {
    load_toml_str_with(text, origin, resolver, &[])
}

/// [`load_toml_str`] with `overrides` applied in order (a later one wins) to the document
/// before any value is checked, so an override meets the file's schema and checks.
pub fn load_toml_str_with(
    text: &str,
    origin: &Path,
    resolver: Resolver<'_>,
    overrides: &[Override],
) -> Result<Scene, SceneError> {
    load_toml_str_at(text, origin, resolver, overrides, None)
}

/// [`load_toml_str_with`] posed at `frame` of the scene's `[animation]`, as
/// [`load_toml_file_at`]. The overrides are applied first, so `-D` can change the keys.
pub fn load_toml_str_at(
    text: &str,
    origin: &Path,
    resolver: Resolver<'_>,
    overrides: &[Override],
    frame: Option<u32>,
) -> Result<Scene, SceneError> {
    // The file on its own first, so its errors keep their line numbers.
    let mut doc: SceneDoc = ::toml::from_str(text).map_err(|e| {
        let offset = e.span().map_or(0, |s| s.start);
        SceneError::parse_at(origin, text, offset, e.message())
    })?;
    if !overrides.is_empty() {
        doc = overrides::apply_to_text(text, origin, overrides)?;
    }
    Loader {
        origin,
        resolver,
        builder: SceneBuilder::new(),
        materials: HashMap::new(),
        frame,
        overrides,
        prototypes: HashMap::new(),
    }
    .load(doc)
}

/// State while turning a parsed document into a scene.
struct Loader<'a> {
    origin: &'a Path,
    resolver: Resolver<'a>,
    builder: SceneBuilder,
    /// Material name to index in the builder.
    materials: HashMap<String, u32>,
    /// The frame `--frame` asks for.
    frame: Option<u32>,
    /// The `-D` overrides already applied to the document (for warnings).
    overrides: &'a [Override],
    /// The elements instances place: their prototype and how many parts it has.
    prototypes: HashMap<Target, (u32, usize)>,
}

impl Loader<'_> {
    fn load(mut self, mut doc: SceneDoc) -> Result<Scene, SceneError> {
        // Posed first: from here on the document is the still of one frame.
        let animation = Animation::new(&doc, self.frame, self.origin)?;
        if let Some(a) = &animation {
            a.pose_objects(&mut doc);
            self.builder.set_frame(a.frame());
            for w in a.shadowed(self.overrides, self.origin) {
                self.builder.warn(w);
            }
        }
        self.render(&doc.render)?;
        for (name, m) in &doc.materials {
            let material = self.material(name, m)?;
            let id = self.builder.add_named_material(name.clone(), material);
            self.materials.insert(name.clone(), id);
        }
        for (i, l) in doc.light.iter().enumerate() {
            let light = self.light(&format!("light[{i}]"), l)?;
            match &l.name {
                Some(name) => self.builder.add_named_light(name, light),
                None => self.builder.add_light(light),
            }
        }
        let targets = instance::targets(&doc, &self)?;
        let instanced: HashSet<Target> = targets.iter().copied().collect();
        for (i, s) in doc.sphere.iter().enumerate() {
            let element = match &s.name {
                Some(n) => format!("sphere[{i}] \"{n}\""),
                None => format!("sphere[{i}]"),
            };
            self.finite(&element, "center", &s.center)?;
            if !(s.radius > 0.0 && s.radius.is_finite()) {
                return Err(self.err(&element, format!("radius {} must be > 0", s.radius)));
            }
            let material = self.material_ref(&element, s.material.as_deref())?;
            let sphere = Sphere {
                center: Vec3::from(s.center),
                radius: s.radius,
            };
            let name = s.name.clone().unwrap_or_else(|| format!("sphere{i}"));
            if instanced.contains(&Target::Sphere(i)) {
                let shape = Shape::Sphere(sphere);
                self.add_prototype_of(Target::Sphere(i), vec![part(name, shape, material)]);
            } else {
                self.builder.add_sphere(name, sphere, material);
            }
        }
        for (i, m) in doc.mesh.iter().enumerate() {
            let element = match &m.name {
                Some(n) => format!("mesh[{i}] \"{n}\""),
                None => format!("mesh[{i}]"),
            };
            let name = m.name.clone().unwrap_or_else(|| format!("mesh{i}"));
            if instanced.contains(&Target::Mesh(i)) {
                let parts = self.mesh_parts(&element, m)?.into_iter();
                let parts = parts.map(|p| {
                    let name = p.object.unwrap_or_else(|| name.clone());
                    part(name, Shape::Mesh(p.mesh), p.material)
                });
                self.add_prototype_of(Target::Mesh(i), parts.collect());
            } else {
                self.add_mesh(&element, name, m)?;
            }
        }
        self.add_instances(&doc.instance, &targets)?;
        let camera = match (&doc.camera, &animation) {
            (Some(c), Some(a)) if a.animates_camera() => self.animated_camera(c, a)?,
            (Some(c), _) => self.camera("camera", c)?,
            (None, _) => {
                let s = self.builder.settings_mut().clone();
                framing_camera(self.builder.bounds(), s.width, s.height)
            }
        };
        let origin = self.origin;
        let mut scene = self
            .builder
            .build(camera)
            .map_err(|e| SceneError::invalid(origin, e.element, e.message))?;
        if let Some(env) = &doc.environment {
            environment::apply(&mut scene, env, origin, self.resolver)?;
        }
        Ok(scene)
    }

    pub(super) fn err(&self, element: &str, message: impl Into<String>) -> SceneError {
        SceneError::invalid(self.origin, element, message)
    }

    /// Checks that every component of `v` is finite.
    fn finite(&self, element: &str, field: &str, v: &[f32]) -> Result<(), SceneError> {
        if v.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(self.err(element, format!("{field} {v:?} must be finite")))
        }
    }

    /// Checks that a colour is finite and non-negative.
    fn color(&self, element: &str, field: &str, c: [f32; 3]) -> Result<Vec3, SceneError> {
        render::color(field, c).map_err(|m| self.err(element, m))
    }

    fn render(&mut self, r: &RenderDoc) -> Result<(), SceneError> {
        let settings = render::merge(&lumis_core::scene::Settings::default(), r)
            .map_err(|m| self.err("render", m))?;
        settings
            .validate()
            .map_err(|m| self.err("render", m.to_string()))?;
        *self.builder.settings_mut() = settings;
        Ok(())
    }

    fn material(&self, name: &str, m: &MaterialDoc) -> Result<Material, SceneError> {
        let e = &format!("materials.{name}");
        let d = Material::default();
        let material = Material {
            diffuse: match m.diffuse {
                Some(c) => Texture::Solid(self.color(e, "diffuse", c)?),
                None => d.diffuse,
            },
            specular: m
                .specular
                .map_or(Ok(d.specular), |c| self.color(e, "specular", c))?,
            shininess: m.shininess.unwrap_or(d.shininess),
            reflectivity: m.reflectivity.unwrap_or(d.reflectivity),
            transmission: m.transmission.unwrap_or(d.transmission),
            ior: m.ior.unwrap_or(d.ior),
            emission: m
                .emission
                .map_or(Ok(d.emission), |c| self.color(e, "emission", c))?,
            normal_map: None,
            textured: None,
            shadow_catcher: m.shadow_catcher.unwrap_or(false),
        };
        self.finite(e, "shininess", &[material.shininess])?;
        if material.shininess < 0.0 {
            return Err(self.err(e, "shininess must be >= 0"));
        }
        for (field, v) in [
            ("reflectivity", material.reflectivity),
            ("transmission", material.transmission),
        ] {
            if !(0.0..=1.0).contains(&v) {
                return Err(self.err(e, format!("{field} {v} must be in [0, 1]")));
            }
        }
        if !(material.ior > 0.0 && material.ior.is_finite()) {
            return Err(self.err(e, format!("ior {} must be > 0", material.ior)));
        }
        Ok(material)
    }

    /// Index of the named material; no name means a default grey one, added on first use.
    fn material_ref(&mut self, element: &str, name: Option<&str>) -> Result<u32, SceneError> {
        let Some(name) = name else {
            let key = "\0default".to_string();
            if let Some(&id) = self.materials.get(&key) {
                return Ok(id);
            }
            let id = self
                .builder
                .add_named_material("default", Material::default());
            self.materials.insert(key, id);
            return Ok(id);
        };
        self.materials.get(name).copied().ok_or_else(|| {
            let mut known: Vec<_> = self
                .materials
                .keys()
                .filter(|k| !k.starts_with('\0'))
                .collect();
            known.sort();
            self.err(
                element,
                format!("unknown material \"{name}\" (defined: {known:?})"),
            )
        })
    }

    fn light(&self, e: &str, l: &LightDoc) -> Result<Light, SceneError> {
        let color = self.color(e, "color", l.color.unwrap_or([1.0; 3]))?;
        let power = color * self.color(e, "intensity", [l.intensity; 3])?;
        match (l.kind, l.position, l.direction) {
            (LightKind::Point, Some(position), None) => {
                self.finite(e, "position", &position)?;
                Ok(Light::Point {
                    position: Vec3::from(position),
                    intensity: power,
                })
            }
            (LightKind::Directional, None, Some(direction)) => {
                self.finite(e, "direction", &direction)?;
                let direction = Vec3::from(direction)
                    .try_normalize()
                    .ok_or_else(|| self.err(e, "direction must be non-zero"))?;
                Ok(Light::Directional {
                    direction,
                    irradiance: power,
                })
            }
            (LightKind::Point, ..) => {
                Err(self.err(e, "a point light takes position, not direction"))
            }
            (LightKind::Directional, ..) => {
                Err(self.err(e, "a directional light takes direction, not position"))
            }
        }
    }

    /// The camera at the animation's frame. Every frame's camera is built, so a sequence
    /// whose camera degenerates anywhere (position reaching look_at, up turning parallel to
    /// the view) fails on its first test render, not in one task of a job array.
    fn animated_camera(&self, c: &CameraDoc, a: &Animation) -> Result<Camera, SceneError> {
        let build = |frame: u32, e: &str| {
            let camera = self.camera(e, &a.camera_at(c, frame))?;
            domain::check_camera(&camera).map_err(|m| self.err(e, m))?;
            Ok(camera)
        };
        for frame in 0..a.frame().count() {
            // Named only on failure: naming a frame searches the keys.
            if build(frame, "camera").is_err() {
                build(frame, &a.camera_element(frame))?;
            }
        }
        let frame = a.frame().number();
        build(frame, &a.camera_element(frame))
    }

    /// The camera of `[camera]` table `c`; errors name it `e`.
    fn camera(&self, e: &str, c: &CameraDoc) -> Result<Camera, SceneError> {
        self.finite(e, "position", &c.position)?;
        self.finite(e, "look_at", &c.look_at)?;
        let up = c.up.unwrap_or([0.0, 1.0, 0.0]);
        self.finite(e, "up", &up)?;
        let (position, look_at, up) = (
            Vec3::from(c.position),
            Vec3::from(c.look_at),
            Vec3::from(up),
        );
        match c.kind.as_deref() {
            None | Some("perspective") if c.height.is_none() => {}
            None | Some("perspective") => {
                return Err(self.err(e, "height is for orthographic cameras; use fov"));
            }
            Some("orthographic") => {
                if c.fov.is_some() || c.aperture.is_some() || c.focus_distance.is_some() {
                    return Err(self.err(
                        e,
                        "an orthographic camera takes height, not fov, aperture or focus_distance",
                    ));
                }
                let height = c
                    .height
                    .ok_or_else(|| self.err(e, "an orthographic camera needs height"))?;
                return Camera::orthographic(position, look_at, up, height)
                    .map_err(|err| self.err(e, err.to_string()));
            }
            Some(other) => {
                return Err(self.err(
                    e,
                    format!("type {other:?}: expected \"perspective\" or \"orthographic\""),
                ));
            }
        }
        let fov = c.fov.unwrap_or(40.0);
        let aperture = c.aperture.unwrap_or(0.0);
        self.finite(e, "fov, aperture", &[fov, aperture])?;
        Camera::look_at(position, look_at, up, fov, aperture, c.focus_distance)
            .map_err(|err| self.err(e, err.to_string()))
    }
}

/// A prototype part.
fn part(name: String, shape: Shape, material: u32) -> Part {
    Part {
        name,
        shape,
        material,
    }
}
