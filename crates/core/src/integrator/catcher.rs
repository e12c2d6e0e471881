//! Shadow catchers (Cycles' flag): a camera ray that meets one shows what lies behind it, the
//! background, multiplied by the shadow the catcher receives, so a render composites onto a
//! photographed plate that has no shadow of the model in it.
//!
//! The shadow is the ratio of the irradiance that reaches the catcher to the irradiance that
//! would reach it with nothing in the way, per channel:
//!
//! ```text
//! factor = (A + sum of visible E_i cos_i) / (A + sum of all E_i cos_i)
//! ```
//!
//! with `A` the ambient irradiance (pi x the constant ambient, or the environment's, both
//! unshadowed in a Whitted renderer) and `E_i cos_i` each light's irradiance on the surface.
//! A white Lambertian ground under the same lights is exactly `factor` times as bright as
//! it would be unshadowed; so a plate photographed without the model, multiplied by it, is the
//! plate with the model's shadow. Under `--transparent` the catcher is premultiplied black
//! with `alpha = 1 - mean(factor)`, and `over` onto the plate gives `plate * (1 - alpha)`;
//! otherwise it shows `background * factor` with alpha 1 (0 on a black background, as a miss).

use super::paths::Split;
use super::{CameraSample, RayCounts, Whitted};
use crate::math::{Ray, Vec3};
use crate::scene::Interaction;

impl Whitted<'_> {
    /// The sample of camera ray `ray` whose first hit `hit` is on a shadow catcher.
    pub(super) fn catcher_sample(
        &self,
        ray: &Ray,
        hit: &Interaction,
        counts: &mut RayCounts,
        split: Option<&mut Split>,
    ) -> CameraSample {
        let factor = self.shadow_factor(ray, hit, counts);
        let shadow = 1.0 - (factor.x + factor.y + factor.z) / 3.0;
        let (radiance, alpha) = if self.transparent || self.background_is_black() {
            (Vec3::ZERO, shadow.clamp(0.0, 1.0))
        } else {
            (self.background(ray.dir) * factor, 1.0)
        };
        if let Some(s) = split {
            s.paths.background = radiance;
            s.shadow = factor;
        }
        CameraSample {
            radiance,
            alpha,
            object: Some(hit.object),
        }
    }

    /// Lit over unshadowed irradiance at the catcher's hit (module docs), 1 where nothing
    /// could light it.
    fn shadow_factor(&self, ray: &Ray, hit: &Interaction, counts: &mut RayCounts) -> Vec3 {
        let s = &hit.surface;
        let (ng, ns) = if ray.dir.dot(s.ng) < 0.0 {
            (s.ng, s.ns)
        } else {
            (-s.ng, -s.ns)
        };
        let ambient = self.ambient(ns) * std::f32::consts::PI;
        let (mut lit, mut all) = (ambient, ambient);
        for (light, &reachable) in self
            .scene
            .lights()
            .iter()
            .zip(&self.analysis.lights_reachable)
        {
            let ls = light.sample(s.p);
            let cos = ns.dot(ls.wi);
            if !reachable || cos <= 0.0 || ng.dot(ls.wi) <= 0.0 || ls.wi == Vec3::ZERO {
                continue;
            }
            let e = ls.irradiance * cos;
            all += e;
            if self.sees_light(s, &ls, counts) {
                lit += e;
            }
        }
        let ratio = |l: f32, a: f32| if a > 0.0 { (l / a).min(1.0) } else { 1.0 };
        Vec3::new(
            ratio(lit.x, all.x),
            ratio(lit.y, all.y),
            ratio(lit.z, all.z),
        )
    }
}
