//! Light-path passes: the beauty of a camera sample split by the way its light arrived, as
//! compositors rebuild and re-balance an image (Blender's DiffDir, GlossDir, GlossInd,
//! TransInd, Emit, Env).
//!
//! The split is made at the camera ray's first hit, as Blender's passes are: everything that
//! arrives through the first mirror bounce is `reflection` (whatever it meets later), through
//! the first refraction `refraction`. With the per-light passes (each light's direct diffuse +
//! specular at that hit) they add up to the beauty:
//!
//! ```text
//! beauty = diffuse + specular + reflection + refraction + emission + ambient + background
//! diffuse + specular = sum over lights of light.<name>
//! ```
//!
//! exactly up to the order of float additions and to `(a + b) x` vs `a x + b x` (the beauty
//! multiplies each light by the sum of its diffuse and Phong factors): a relative error of a
//! few ulps per term, far below anything visible. A sample that hits the radiance ceiling
//! (`MAX_SAMPLE_RADIANCE`, 1e30) is capped in the beauty and not in the passes.

use crate::math::Vec3;

/// The light-path passes of one camera sample (or their sum over a pixel's samples).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LightPaths {
    /// Direct light on the diffuse (Lambert) lobe at the first hit.
    pub diffuse: Vec3,
    /// Direct Phong highlights at the first hit.
    pub specular: Vec3,
    /// Everything arriving through the first hit's mirror ray.
    pub reflection: Vec3,
    /// Everything arriving through the first hit's refracted ray.
    pub refraction: Vec3,
    /// The first hit's own emission.
    pub emission: Vec3,
    /// The first hit's ambient term (the environment's diffuse part when there is one).
    pub ambient: Vec3,
    /// What an escaping camera ray sees (and, on a shadow catcher, the darkened background).
    pub background: Vec3,
}

impl LightPaths {
    /// The passes' layer names, in [`LightPaths::values`] order.
    pub const NAMES: [&'static str; 7] = [
        "diffuse",
        "specular",
        "reflection",
        "refraction",
        "emission",
        "ambient",
        "background",
    ];

    /// The passes in [`LightPaths::NAMES`] order.
    pub fn values(&self) -> [Vec3; 7] {
        [
            self.diffuse,
            self.specular,
            self.reflection,
            self.refraction,
            self.emission,
            self.ambient,
            self.background,
        ]
    }
}

/// Where [`super::Whitted`] writes the split of one camera sample: the light paths and one
/// entry per scene light (its direct contribution at the first hit).
#[derive(Debug)]
pub struct Split<'a> {
    /// The light-path passes.
    pub paths: LightPaths,
    /// Per light, in scene order.
    pub lights: &'a mut [Vec3],
    /// What a plate behind a shadow catcher is multiplied by (per channel: lit over
    /// unshadowed irradiance); 1 wherever the camera ray met no catcher.
    pub shadow: Vec3,
}

impl<'a> Split<'a> {
    /// An empty split writing per-light values into `lights` (one per scene light, zeroed here).
    pub fn new(lights: &'a mut [Vec3]) -> Self {
        lights.fill(Vec3::ZERO);
        Self {
            paths: LightPaths::default(),
            lights,
            shadow: Vec3::ONE,
        }
    }
}
