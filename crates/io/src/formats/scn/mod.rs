//! The `.scn` scene format of the paper's ray tracer (see `../shared/paper-scenes/README.md`).
//!
//! Whitespace-separated tokens, `#` comments out the rest of a line, each statement starts with
//! a keyword. The original's shading maps onto lumis's materials without a second integrator:
//! - ambient `0.2 * colour`: `Settings::ambient = 0.2`;
//! - per unshadowed light `I * (colour * cos + cos_r^shininess)`, no distance falloff: lights
//!   become [`Light::Unattenuated`] with irradiance `pi * I` (lumis's Lambert is `kd / pi`)
//!   and the Phong colour is `2 / (n + 2)` so lumis's normalised lobe peaks at exactly 1
//!   (lumis weights the lobe by the cosine of incidence too, the original does not: broad
//!   highlights of low shininess come out dimmer; docs/paper.md measures it);
//! - `reflectivity` → mirror weight; `Glass` → transmission 1 with Fresnel, no diffuse.
//!
//! Defaults when a statement is missing, the original's (its `main` and `RayTracer`
//! constructor): camera at the origin looking down -z with up +y, `cameraScreenWidth 1920`,
//! `maxReflections 10`, `dispersion 5` (so depth of field is on), 1920x1080, 1 sample,
//! `depthComplexity 5` lens rays per sample (the original takes it from its command line; the
//! paper used 5). A negative `dispersion` turns depth of field off (a pinhole, one ray per
//! sample); `dispersion 0` makes the original trace `depthComplexity` identical rays, for which
//! lumis traces one pinhole ray: the image is the same. The PNG is written with
//! [`DisplayTransform::Clamp`] (colour x 255, clamped, no transfer curve) as the original writes
//! its TGA; the contribution cutoff is 0 as the original traces every branch.
//!
//! Known defects of the original that lumis does not copy (each found by rebuilding the
//! original with that one thing changed):
//! - it multiplies the running diffuse sum by each light's intensity (`sum = (sum + colour *
//!   cos) * I`), so a light's diffuse term is scaled again by every later light's intensity:
//!   scenes with several lights come out too dark (intensities below 1) or too bright;
//! - it reflects a position (the incoming ray's origin: the camera, or the previous hit point)
//!   about the normal instead of the ray direction, so mirrors show the wrong part of the scene;
//! - its median split (the BSMP variant) puts a primitive whose centroid lies exactly on the
//!   split value into neither child: one object vanishes from ballsInAPit and tumbledStones;
//! - its lens jitter moves the ray origin along world x and y instead of the camera's axes;
//! - it gives every refracted ray a recursion budget of 1 whatever is left, so glass can cut
//!   internal reflections short and never stops a chain of refractions (lumis counts each
//!   refraction as a bounce against `maxReflections`);
//! - it knows the medium only from the ray: every hit on glass is taken as entering it, so a
//!   refracted ray reaching the far side goes from glass into glass (no bend, no reflection)
//!   and a camera inside glass (tumbledStones' dome) refracts as if entering it;
//! - it shades a triangle with its winding normal, never turned towards the viewer, so a
//!   triangle seen from behind (triangleTest1's checkered one) gets only ambient light;
//! - it truncates colour x 255 to the code value where lumis rounds (half a level darker).
//!
//! The noise textures follow the original's formulas (see [`Texture`]) over lumis's own
//! Perlin noise, so they look alike but are not the same pixels.

mod camera;
pub mod mesh_m;

use super::{SceneError, read_text};
use camera::CameraSpec;
use lumis_core::film::DisplayTransform;
use lumis_core::geometry::{Mesh, Sphere};
use lumis_core::light::Light;
use lumis_core::material::{Material, Texture};
use lumis_core::math::{Aabb, Mat4, Vec3};
use lumis_core::scene::{MAX_DEPTH, MAX_LENS_SAMPLES, Scene, SceneBuilder};
use lumis_core::texture::NormalMap;
pub use mesh_m::{load_m_file, parse_m};
use std::collections::HashMap;
use std::path::Path;

/// Loads a `.scn` file; `model` paths resolve relative to its folder.
pub fn load_scn_file(path: &Path) -> Result<Scene, SceneError> {
    let text = read_text(path)?;
    parse_scn(&text, path)
}

/// Parses `.scn` text; `path` names it in messages and anchors relative `model` paths.
pub fn parse_scn(text: &str, path: &Path) -> Result<Scene, SceneError> {
    let tokens: Vec<(usize, &str)> = text
        .lines()
        .enumerate()
        .flat_map(|(i, l)| {
            l.split_whitespace()
                .take_while(|t| !t.starts_with('#'))
                .map(move |t| (i + 1, t))
        })
        .collect();
    let mut p = Parser {
        tokens,
        pos: 0,
        path,
        materials: HashMap::new(),
    };
    let mut b = SceneBuilder::new();
    let st = b.settings_mut();
    (
        st.width,
        st.height,
        st.spp,
        st.max_depth,
        st.ambient,
        st.lens_samples,
    ) = (1920, 1080, 1, 10, Vec3::splat(0.2), 5);
    // The original traces every reflection and refraction branch: no contribution cutoff.
    st.cutoff = 0.0;
    // The original writes colour x 255, clamped: its images are display-referred.
    st.display = DisplayTransform::Clamp;
    let mut cam = CameraSpec::default();
    let mut count = 0usize;
    while let Some((line, keyword)) = p.next() {
        match keyword {
            "cameraPosition" => cam.position = p.vec3("camera position")?,
            "cameraLookAt" => cam.look_at = p.vec3("camera look-at point")?,
            "cameraUp" => cam.up = p.vec3("camera up vector")?,
            "cameraScreenWidth" => cam.screen_width = p.positive("screen width")?,
            "dispersion" => cam.dispersion = p.number("dispersion")?,
            "depthComplexity" => {
                b.settings_mut().lens_samples =
                    p.count("depth complexity", MAX_LENS_SAMPLES)?.max(1)
            }
            "maxReflections" => {
                b.settings_mut().max_depth = p.count("maximum reflections", MAX_DEPTH)?
            }
            "light" => {
                let position = p.vec3("light position")?;
                let intensity = p.number("light intensity")?;
                let irradiance = Vec3::splat(std::f32::consts::PI * intensity);
                b.add_light(Light::Unattenuated {
                    position,
                    irradiance,
                });
            }
            "sphere" => {
                let center = p.vec3("sphere centre")?;
                let radius = p.positive("sphere radius")?;
                let m = p.material(&mut b)?;
                count += 1;
                b.add_sphere(
                    format!("sphere{count}@{line}"),
                    Sphere { center, radius },
                    m,
                );
            }
            "triangle" => {
                let v = [
                    p.vec3("triangle vertex")?,
                    p.vec3("triangle vertex")?,
                    p.vec3("triangle vertex")?,
                ];
                let m = p.material(&mut b)?;
                let mesh = Mesh::new(v.to_vec(), None, None, vec![[0, 1, 2]])
                    .map_err(|e| p.err(line, e.to_string()))?;
                count += 1;
                b.add_mesh(format!("triangle{count}@{line}"), mesh, m);
            }
            "model" => {
                let file = p.word("model file")?;
                let size = p.positive("model size")?;
                let offset = p.vec3("model translation")?;
                let m = p.material(&mut b)?;
                let full = path.parent().unwrap_or(Path::new(".")).join(file);
                let mesh = load_m_file(&full).map_err(|source| SceneError::LineAsset {
                    path: path.to_owned(),
                    line,
                    file: full.clone(),
                    source: Box::new(source),
                })?;
                b.add_mesh(file.to_owned(), place_model(mesh, size, offset), m);
            }
            "material" => {
                let name = p.word("material name")?;
                let m = p.material_spec()?;
                p.materials.insert(name.to_owned(), m);
            }
            "startingMaterial" => {
                let m = p.material_spec()?;
                // Only a transmissive medium changes anything: its index becomes the outside's.
                b.settings_mut().medium_ior = if m.transmits() { m.ior } else { 1.0 };
            }
            other => return Err(p.err(line, format!("unknown keyword {other:?}"))),
        }
    }
    let camera = cam.build().map_err(|e| p.err(0, format!("camera: {e}")))?;
    b.settings_mut()
        .validate()
        .map_err(|e| p.err(0, format!("render settings: {e}")))?;
    b.build(camera)
        .map_err(|e| SceneError::invalid(path, e.element, e.message))
}

/// Centres the mesh's bounds at the origin, scales its diagonal to `size`, then translates.
fn place_model(mesh: Mesh, size: f32, offset: Vec3) -> Mesh {
    let bounds: Aabb = mesh.bounds();
    let diagonal = bounds.extent().length().max(f32::MIN_POSITIVE);
    let m = Mat4::from_translation(offset)
        * Mat4::from_scale(Vec3::splat(size / diagonal))
        * Mat4::from_translation(-bounds.center());
    mesh.transformed(&m)
}

struct Parser<'a> {
    tokens: Vec<(usize, &'a str)>,
    pos: usize,
    path: &'a Path,
    materials: HashMap<String, Material>,
}

impl<'a> Parser<'a> {
    fn next(&mut self) -> Option<(usize, &'a str)> {
        let t = self.tokens.get(self.pos).copied();
        self.pos += 1;
        t
    }

    fn err(&self, line: usize, message: String) -> SceneError {
        SceneError::Line {
            path: self.path.to_owned(),
            line,
            message,
        }
    }

    /// Line of the most recent token (for "ran out" messages).
    fn line(&self) -> usize {
        self.tokens
            .get(self.pos.saturating_sub(1))
            .or(self.tokens.last())
            .map_or(1, |t| t.0)
    }

    fn word(&mut self, what: &str) -> Result<&'a str, SceneError> {
        self.next()
            .map(|t| t.1)
            .ok_or_else(|| self.err(self.line(), format!("expected {what}, found end of file")))
    }

    fn number(&mut self, what: &str) -> Result<f32, SceneError> {
        let (line, t) = self
            .next()
            .ok_or_else(|| self.err(self.line(), format!("expected {what}, found end of file")))?;
        match t.parse::<f32>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.err(
                line,
                format!("expected {what} (a finite number), found {t:?}"),
            )),
        }
    }

    fn positive(&mut self, what: &str) -> Result<f32, SceneError> {
        let v = self.number(what)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(self.line(), format!("{what} must be positive, found {v}")))
        }
    }

    /// A whole number in `0..=max` (the renderer's limits: see [`lumis_core::scene::Settings::validate`]).
    fn count(&mut self, what: &str, max: u32) -> Result<u32, SceneError> {
        let v = self.number(what)?;
        if v >= 0.0 && v.fract() == 0.0 && v <= max as f32 {
            Ok(v as u32)
        } else {
            Err(self.err(
                self.line(),
                format!("{what} must be a whole number in 0..={max}, found {v}"),
            ))
        }
    }

    fn vec3(&mut self, what: &str) -> Result<Vec3, SceneError> {
        Ok(Vec3::new(
            self.number(what)?,
            self.number(what)?,
            self.number(what)?,
        ))
    }

    /// A material colour: every `.scn` colour is a reflectance, so in [0, 1].
    fn colour(&mut self) -> Result<Vec3, SceneError> {
        let c = self.vec3("colour component")?;
        if c.min_element() < 0.0 || c.max_element() > 1.0 {
            return Err(self.err(
                self.line(),
                format!("colour {c} must have components in [0, 1]"),
            ));
        }
        Ok(c)
    }

    /// A reflectivity: in [0, 1], or the paper's -1 for none (read as 0).
    fn reflectivity(&mut self) -> Result<f32, SceneError> {
        let r = self.number("reflectivity")?;
        if r == -1.0 || (0.0..=1.0).contains(&r) {
            Ok(r.max(0.0))
        } else {
            Err(self.err(
                self.line(),
                format!("reflectivity {r} must be in [0, 1] (or -1 for none)"),
            ))
        }
    }

    /// A MATERIAL where geometry expects one, added to the scene; returns its index.
    fn material(&mut self, b: &mut SceneBuilder) -> Result<u32, SceneError> {
        let m = self.material_spec()?;
        Ok(b.add_material(m))
    }

    /// A material: a defined name, or a type with its parameters and a normal map.
    fn material_spec(&mut self) -> Result<Material, SceneError> {
        let (line, kind) = self.next().ok_or_else(|| {
            self.err(self.line(), "expected a material, found end of file".into())
        })?;
        if let Some(m) = self.materials.get(kind) {
            return Ok(m.clone());
        }
        let mut m = Material {
            specular: Vec3::ZERO,
            ..Material::default()
        };
        let (diffuse, shininess, reflectivity) = match kind {
            "FlatColor" => (Texture::Solid(self.colour()?), -1.0, -1.0),
            "ShinyColor" => (
                Texture::Solid(self.colour()?),
                self.number("shininess")?,
                self.reflectivity()?,
            ),
            "Glass" => {
                m.ior = self.positive("refractive index")?;
                m.transmission = 1.0;
                (Texture::Solid(Vec3::ZERO), self.number("shininess")?, -1.0)
            }
            "Checkerboard" | "Turbulence" | "Marble" | "Wood" => {
                let (a, b_, scale) = (
                    self.colour()?,
                    self.colour()?,
                    self.positive("texture scale")?,
                );
                let t = match kind {
                    // `from_scn_scale` below moves the grid to the original's corner.
                    "Checkerboard" => Texture::Checkerboard {
                        a,
                        b: b_,
                        scale,
                        origin: Vec3::ZERO,
                    },
                    "Turbulence" => Texture::Turbulence { a, b: b_, scale },
                    "Marble" => Texture::Marble { a, b: b_, scale },
                    _ => Texture::Wood { a, b: b_, scale },
                };
                (t, self.number("shininess")?, self.reflectivity()?)
            }
            "CrissCross" => {
                let (a, b_, c) = (self.colour()?, self.colour()?, self.colour()?);
                let scale = self.positive("texture scale")?;
                (
                    Texture::CrissCross { a, b: b_, c, scale },
                    self.number("shininess")?,
                    self.reflectivity()?,
                )
            }
            other => {
                return Err(self.err(
                    line,
                    format!(
                        "unknown material {other:?}; expected FlatColor, ShinyColor, Checkerboard, Glass, Turbulence, \
                         Marble, Wood, CrissCross or a name defined with `material`"
                    ),
                ));
            }
        };
        // The .scn scales are frequencies for the noise kinds; lumis's are lengths.
        m.diffuse = diffuse.from_scn_scale();
        if shininess > 0.0 {
            m.shininess = shininess;
            m.specular = Vec3::splat(2.0 / (shininess + 2.0));
        }
        m.reflectivity = reflectivity.max(0.0);
        m.normal_map = self.normal_map()?;
        Ok(m)
    }

    fn normal_map(&mut self) -> Result<Option<NormalMap>, SceneError> {
        match self.next() {
            Some((_, "null")) => Ok(None),
            Some((_, "NormalMap")) => Ok(Some(NormalMap {
                scale: self.positive("normal map scale")?,
                amount: self.number("normal map amount")?,
            })),
            Some((line, t)) => Err(self.err(
                line,
                format!("expected `null` or `NormalMap scale amount`, found {t:?}"),
            )),
            None => Err(self.err(
                self.line(),
                "expected `null` or `NormalMap`, found end of file".into(),
            )),
        }
    }
}
