//! Camera rays: where a sample starts (its first hit, or the environment it escapes to),
//! alone, in packets, or split into light-path passes; and what escaping rays see and where
//! ambient light comes from.

use super::paths::Split;
use super::{RayCounts, Whitted};
use crate::accel::PACKET;
use crate::math::{Ray, Vec3};
use crate::scene::Interaction;

/// Radiance along a camera ray, and how much of the pixel it covers (for alpha).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CameraSample {
    /// Incoming radiance.
    pub radiance: Vec3,
    /// Coverage: 1 where the ray hit geometry or escaped into a non-black background, 0 where
    /// it escaped into black (or anything, under `--transparent`); on a shadow catcher under
    /// `--transparent`, the opacity of the shadow.
    pub alpha: f32,
    /// The object the ray hit first (what Cryptomatte names the sample by); `None` on a miss.
    pub object: Option<u32>,
}

impl Whitted<'_> {
    /// Radiance arriving along camera ray `ray`.
    pub fn camera_ray(&self, ray: &Ray, counts: &mut RayCounts) -> CameraSample {
        counts.camera += 1;
        let hit = self.world.intersect(ray, &mut counts.traversal);
        self.camera_sample(ray, hit, counts, None)
    }

    /// [`Whitted::camera_ray`], its radiance also split by light path and light into `split`
    /// (the light-path passes, [`super::paths`]).
    pub fn camera_ray_split(
        &self,
        ray: &Ray,
        counts: &mut RayCounts,
        split: &mut Split,
    ) -> CameraSample {
        counts.camera += 1;
        let hit = self.world.intersect(ray, &mut counts.traversal);
        self.camera_sample(ray, hit, counts, Some(split))
    }

    /// [`Whitted::camera_ray`] of each of `rays` (up to [`PACKET`]) into `out`, their nearest
    /// hits found together where they can be ([`World::intersect_packet`]); the same samples.
    pub fn camera_rays(&self, rays: &[Ray], counts: &mut RayCounts, out: &mut [CameraSample]) {
        counts.camera += rays.len() as u64;
        let mut hits = [None; PACKET];
        let hits = &mut hits[..rays.len()];
        self.world
            .intersect_packet(rays, &mut counts.traversal, hits);
        for ((o, ray), hit) in out.iter_mut().zip(rays).zip(hits.iter()) {
            *o = self.camera_sample(ray, *hit, counts, None);
        }
    }

    /// The sample of camera ray `ray` that found `hit`.
    #[inline(always)]
    fn camera_sample(
        &self,
        ray: &Ray,
        hit: Option<Interaction>,
        counts: &mut RayCounts,
        split: Option<&mut Split>,
    ) -> CameraSample {
        match hit {
            Some(hit) if self.catchers && self.is_catcher(&hit) => {
                self.catcher_sample(ray, &hit, counts, split)
            }
            Some(hit) => CameraSample {
                // The split is a separate instance: the common path carries none of its tests.
                radiance: match (self.all, split.is_some()) {
                    (true, true) => self.shade::<true, true>(ray, &hit, 0, 1.0, counts, split),
                    (true, false) => self.shade::<true, false>(ray, &hit, 0, 1.0, counts, None),
                    (false, true) => self.shade::<false, true>(ray, &hit, 0, 1.0, counts, split),
                    (false, false) => self.shade::<false, false>(ray, &hit, 0, 1.0, counts, None),
                },
                alpha: 1.0,
                object: Some(hit.object),
            },
            None => {
                let (radiance, alpha) = if self.transparent {
                    (Vec3::ZERO, 0.0)
                } else {
                    let bg = self.background(ray.dir);
                    (bg, if self.background_is_black() { 0.0 } else { 1.0 })
                };
                if let Some(s) = split {
                    s.paths.background = radiance;
                }
                CameraSample {
                    radiance,
                    alpha,
                    object: None,
                }
            }
        }
    }

    /// What a ray leaving in direction `dir` that escapes the scene sees.
    #[inline]
    pub(super) fn background(&self, dir: Vec3) -> Vec3 {
        match self.env {
            Some(env) => env.radiance(dir),
            None => self.scene.settings().background,
        }
    }

    /// Whether every escaping ray sees black (alpha is then 0 there, as for a transparent
    /// miss).
    pub(super) fn background_is_black(&self) -> bool {
        match self.env {
            Some(env) => env.is_black(),
            None => self.scene.settings().background == Vec3::ZERO,
        }
    }

    /// Ambient radiance reflected per unit albedo at a point with shading normal `ns`: the
    /// environment's irradiance over pi (a white Lambertian surface under it), or the constant
    /// ambient of the settings when there is no environment.
    #[inline]
    pub(super) fn ambient(&self, ns: Vec3) -> Vec3 {
        match self.env {
            Some(env) => env.irradiance(ns) * std::f32::consts::FRAC_1_PI,
            None => self.scene.settings().ambient,
        }
    }
}
