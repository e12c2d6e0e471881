//! The RGB pass layers a render fills besides the beauty, and how one camera sample's split
//! lands in them.

use crate::film::SHADOW_PASS;
use crate::integrator::{LightPaths, Split};
use crate::math::Vec3;
use crate::scene::Scene;

/// Which RGB passes a render fills ([`crate::integrator::paths`]); the shadow catcher's
/// `shadow` pass comes with any scene that has a catcher.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PassRequest {
    /// `diffuse`, `specular`, `reflection`, `refraction`, `emission`, `ambient`, `background`.
    pub light_paths: bool,
    /// `light.<name>` for each light: its direct contribution at the first hit.
    pub lights: bool,
}

/// The pass layers of one render, in film order: the light paths, the lights, the shadow.
pub(super) struct PassLayout {
    light_paths: bool,
    lights: Vec<String>,
    shadow: bool,
}

impl PassLayout {
    pub(super) fn new(scene: &Scene, request: PassRequest) -> Self {
        Self {
            light_paths: request.light_paths,
            lights: if request.lights {
                scene.light_names().to_vec()
            } else {
                Vec::new()
            },
            shadow: scene.materials().iter().any(|m| m.shadow_catcher),
        }
    }

    /// Values per pixel.
    pub(super) fn count(&self) -> usize {
        usize::from(self.light_paths) * LightPaths::NAMES.len()
            + self.lights.len()
            + usize::from(self.shadow)
    }

    /// Whether the samples are traced one by one into a [`Split`] (any pass at all: the
    /// shadow pass comes from the split too, so the common path carries none of it).
    pub(super) fn splits(&self) -> bool {
        self.light_paths || !self.lights.is_empty() || self.shadow
    }

    /// Adds one split sample's passes to a pixel's sums `out` (film order).
    pub(super) fn accumulate(&self, split: &Split, out: &mut [Vec3]) {
        let mut at = 0;
        if self.light_paths {
            for (o, v) in out.iter_mut().zip(split.paths.values()) {
                *o += v;
            }
            at = LightPaths::NAMES.len();
        }
        if !self.lights.is_empty() {
            for (o, v) in out[at..].iter_mut().zip(split.lights.iter()) {
                *o += *v;
            }
            at += self.lights.len();
        }
        if self.shadow {
            out[at] += split.shadow;
        }
    }

    /// Layer names and whether each is radiance, in film order.
    pub(super) fn names(&self) -> Vec<(String, bool)> {
        let paths = LightPaths::NAMES
            .iter()
            .filter(|_| self.light_paths)
            .map(|n| (n.to_string(), true));
        let lights = self.lights.iter().map(|n| (format!("light.{n}"), true));
        let shadow = self
            .shadow
            .then(|| (SHADOW_PASS.to_string(), false))
            .into_iter();
        paths.chain(lights).chain(shadow).collect()
    }
}
