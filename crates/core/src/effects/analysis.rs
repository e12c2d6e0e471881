//! The scene-level and per-material half of the effect decisions, taken once per render.

use super::EffectMode;
use crate::material::{Material, Texture};
use crate::scene::Scene;
use serde::Serialize;

/// One effect: on or off, and why.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Decision {
    /// Whether the render simulates it.
    pub on: bool,
    /// Plain-words reason, e.g. "no material transmits".
    pub reason: String,
}

impl Decision {
    fn new(on: bool, reason: impl Into<String>) -> Self {
        Self {
            on,
            reason: reason.into(),
        }
    }
}

/// What one material can do, read once per render so shading tests a flag, not the material.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MaterialTraits {
    /// Direct light can change its colour (non-black diffuse or a Phong lobe).
    pub lit: bool,
    /// It has a Phong highlight (non-zero specular colour and a positive exponent).
    pub phong: bool,
    /// It spawns mirror rays (its own reflectivity or the Fresnel part of transmission).
    pub reflects: bool,
    /// It spawns refraction rays.
    pub transmits: bool,
    /// It emits light.
    pub emits: bool,
}

impl MaterialTraits {
    /// The traits of `m`; under [`EffectMode::All`] every trait is on.
    pub fn of(m: &Material, mode: EffectMode) -> Self {
        if mode == EffectMode::All {
            return Self {
                lit: true,
                phong: true,
                reflects: true,
                transmits: true,
                emits: true,
            };
        }
        Self {
            lit: m.is_lit(),
            phong: m.has_phong(),
            reflects: m.reflects(),
            transmits: m.transmits(),
            emits: m.emission != crate::math::Vec3::ZERO,
        }
    }
}

/// Every scene-level effect decision of one render, with its reason.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Analysis {
    /// `auto` or `all`.
    pub mode: EffectMode,
    /// Shadow rays towards lights.
    pub shadows: Decision,
    /// Mirror reflection rays.
    pub reflection: Decision,
    /// Refraction rays.
    pub refraction: Decision,
    /// Lens rays through an aperture.
    pub depth_of_field: Decision,
    /// Centre rays for the depth, normal and id layers.
    pub aov: Decision,
    /// Phong highlights.
    pub phong: Decision,
    /// Texture evaluation (anything but a solid colour).
    pub textures: Decision,
    /// Normal-map perturbation of the shading normal.
    pub normal_maps: Decision,
    /// Emitted radiance.
    pub emission: Decision,
    /// Whether the reflection/refraction cutoff is applied.
    pub cutoff: Decision,
    /// What escaping rays are worth: an environment map (never skipped: a ray that escapes
    /// is no longer worth zero), a constant background, or black.
    pub environment: Decision,
    /// Lens rays traced per pixel sample.
    pub lens_rays: u32,
    /// Per light: whether it can light anything (false: zero intensity).
    pub lights_reachable: Vec<bool>,
    #[serde(skip)]
    materials: Vec<MaterialTraits>,
}

impl Analysis {
    /// Decides what a render of `scene` simulates under `mode`; `aov_layers` says whether the
    /// output has depth/normal/id layers (an EXR) or not (a PNG only).
    pub fn new(scene: &Scene, mode: EffectMode, aov_layers: bool) -> Self {
        let all = mode == EffectMode::All;
        let used: Vec<&Material> = used_materials(scene);
        let count = |f: &dyn Fn(&Material) -> bool| used.iter().filter(|m| f(m)).count();
        let of = |n: usize| format!("{n} of {} materials", used.len());
        let st = scene.settings();
        let lights = scene.lights();
        let reachable: Vec<bool> = lights.iter().map(|l| all || !l.is_dark()).collect();
        let n_reachable = reachable.iter().filter(|r| **r).count();
        let lit = count(&Material::is_lit);
        let forced = |d: Decision| {
            if all {
                Decision::new(true, format!("forced by --effects all ({})", d.reason))
            } else {
                d
            }
        };

        let shadows = forced(if lights.is_empty() {
            Decision::new(false, "the scene has no lights")
        } else if n_reachable == 0 {
            Decision::new(false, "every light has zero intensity")
        } else if lit == 0 {
            Decision::new(false, "no material responds to light")
        } else {
            Decision::new(
                true,
                format!(
                    "{n_reachable} of {} lights reachable; {} respond to light",
                    lights.len(),
                    of(lit)
                ),
            )
        });
        let bounce = |verb: &str, n: usize| {
            forced(if st.max_depth == 0 {
                Decision::new(false, "max depth is 0")
            } else if n == 0 {
                Decision::new(false, format!("no material {verb}s"))
            } else {
                let s = if n == 1 { "s" } else { "" };
                Decision::new(true, format!("{} {verb}{s}", of(n)))
            })
        };
        let reflection = bounce("reflect", count(&Material::reflects));
        let refraction = bounce("transmit", count(&Material::transmits));

        let cam = scene.camera();
        let lens_rays = if cam.has_depth_of_field() {
            st.lens_samples.max(1)
        } else {
            1
        };
        let depth_of_field = if cam.has_depth_of_field() {
            Decision::new(
                true,
                format!("lens aperture; {lens_rays} lens ray(s) per sample"),
            )
        } else if st.lens_samples > 1 {
            Decision::new(
                false,
                format!(
                    "pinhole camera: the {} lens rays asked per sample would all be the same \
                     ray, so 1 is traced",
                    st.lens_samples
                ),
            )
        } else {
            Decision::new(false, "pinhole camera")
        };
        let aov = forced(if aov_layers {
            Decision::new(true, "the output has depth, normal and id layers")
        } else {
            Decision::new(false, "no output has depth, normal or id layers (PNG only)")
        });
        let feature = |name: &str, n: usize| Decision::new(n > 0, format!("{} {name}", of(n)));
        let phong = forced(feature(
            "have a Phong highlight",
            count(&Material::has_phong),
        ));
        let textures = feature(
            "are textured",
            count(&|m| !matches!(m.diffuse, Texture::Solid(_)) || m.textured.is_some()),
        );
        let normal_maps = feature(
            "have a normal map",
            count(&|m| {
                m.normal_map.is_some()
                    || m.textured
                        .as_ref()
                        .is_some_and(|t| t.normal_texture.is_some())
            }),
        );
        let emission = forced(feature(
            "emit",
            count(&|m| m.emission != crate::math::Vec3::ZERO),
        ));
        let cutoff = if all {
            Decision::new(false, "forced off by --effects all")
        } else if st.cutoff > 0.0 {
            Decision::new(
                true,
                format!("branches weighing less than {} are not traced", st.cutoff),
            )
        } else {
            Decision::new(false, "cutoff 0: every branch up to max depth is traced")
        };
        let environment = match scene.environment() {
            Some(env) if !env.is_black() => Decision::new(
                true,
                format!(
                    "escaping rays see {} ({}x{}); ambient light is its diffuse irradiance{}",
                    env.source(),
                    env.map().width(),
                    env.map().height(),
                    if env.sun().is_some() {
                        "; its sun is the light \"sun\""
                    } else {
                        ""
                    }
                ),
            ),
            Some(_) => Decision::new(false, "the environment map is black"),
            None if st.background != crate::math::Vec3::ZERO => Decision::new(
                false,
                format!(
                    "no environment: escaping rays see the background {}",
                    st.background
                ),
            ),
            None => Decision::new(false, "no environment: escaping rays see black"),
        };
        Self {
            mode,
            shadows,
            reflection,
            refraction,
            depth_of_field,
            aov,
            phong,
            textures,
            normal_maps,
            emission,
            cutoff,
            environment,
            lens_rays,
            lights_reachable: reachable,
            materials: scene
                .materials()
                .iter()
                .map(|m| MaterialTraits::of(m, mode))
                .collect(),
        }
    }

    /// The traits of material `index` (as in `Scene::materials`).
    pub fn material(&self, index: u32) -> MaterialTraits {
        self.materials[index as usize]
    }

    /// Every decision with its name, in report order.
    pub fn decisions(&self) -> [(&'static str, &Decision); 11] {
        [
            ("shadows", &self.shadows),
            ("reflection", &self.reflection),
            ("refraction", &self.refraction),
            ("depth of field", &self.depth_of_field),
            ("aov rays", &self.aov),
            ("phong", &self.phong),
            ("textures", &self.textures),
            ("normal maps", &self.normal_maps),
            ("emission", &self.emission),
            ("cutoff", &self.cutoff),
            ("environment", &self.environment),
        ]
    }
}

/// The materials some object uses (a file may define materials nothing references).
fn used_materials(scene: &Scene) -> Vec<&Material> {
    let mut seen = vec![false; scene.materials().len()];
    for o in scene.objects() {
        seen[o.material as usize] = true;
    }
    scene
        .materials()
        .iter()
        .zip(seen)
        .filter_map(|(m, s)| s.then_some(m))
        .collect()
}
