//! Whitted-style ray tracing: direct light with hard shadows, recursive mirror reflection and
//! Fresnel-weighted refraction, up to `max_depth` bounces. Rays for effects the scene does not
//! call for (see [`crate::scene::Effects`]) are never traced.

use super::RayCounts;
use crate::accel::Accel;
use crate::geometry::{Offset, SurfacePoint};
use crate::material::{Material, fresnel_dielectric, reflect, refract};
use crate::math::{Ray, Vec3};
use crate::scene::{Effects, Interaction, Scene};

/// The Whitted integrator over one scene and its accelerator.
pub struct Whitted<'a> {
    scene: &'a Scene,
    accel: &'a Accel,
    effects: Effects,
    max_depth: u32,
    medium_ior: f32,
    offset: Offset,
    cutoff: f32,
}

/// Radiance along a camera ray, and whether it saw anything (for alpha).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSample {
    /// Incoming radiance.
    pub radiance: Vec3,
    /// True when the ray hit geometry or escaped into a non-black background.
    pub opaque: bool,
}

impl<'a> Whitted<'a> {
    /// An integrator that traces only the effects `scene.effects()` reports.
    pub fn new(scene: &'a Scene, accel: &'a Accel) -> Self {
        let st = scene.settings();
        Self {
            scene,
            accel,
            effects: scene.effects(),
            max_depth: st.max_depth,
            medium_ior: st.medium_ior,
            offset: st.offset,
            cutoff: st.cutoff,
        }
    }

    /// The accelerator rays are traced through.
    pub fn accel(&self) -> &'a Accel {
        self.accel
    }

    /// Radiance arriving along camera ray `ray`.
    pub fn camera_ray(&self, ray: &Ray, counts: &mut RayCounts) -> CameraSample {
        counts.camera += 1;
        match self.scene.intersect(self.accel, ray, &mut counts.traversal) {
            Some(hit) => CameraSample {
                radiance: self.shade(ray, &hit, 0, 1.0, counts),
                opaque: true,
            },
            None => {
                let bg = self.scene.settings().background;
                CameraSample {
                    radiance: bg,
                    opaque: bg != Vec3::ZERO,
                }
            }
        }
    }

    /// Radiance along a secondary ray at bounce `depth`, whose radiance enters the pixel
    /// multiplied by `weight`.
    fn trace(&self, ray: &Ray, depth: u32, weight: f32, counts: &mut RayCounts) -> Vec3 {
        match self.scene.intersect(self.accel, ray, &mut counts.traversal) {
            Some(hit) => self.shade(ray, &hit, depth, weight, counts),
            None => self.scene.settings().background,
        }
    }

    /// True when a branch of this weight is worth tracing; counts the ones cut.
    fn keep_branch(&self, weight: f32, counts: &mut RayCounts) -> bool {
        let keep = weight >= self.cutoff;
        counts.cut += u64::from(!keep);
        keep
    }

    /// Radiance leaving `hit` back along `ray`; `weight` is the product of the reflection and
    /// transmission factors that brought the camera ray here.
    fn shade(
        &self,
        ray: &Ray,
        hit: &Interaction,
        depth: u32,
        weight: f32,
        counts: &mut RayCounts,
    ) -> Vec3 {
        let m = self.scene.material_of(hit.object);
        let s = &hit.surface;
        let wo = -ray.dir.normalize();
        // Shade the side the ray arrived on; `entering` tells refraction which way it goes.
        let entering = ray.dir.dot(s.ng) < 0.0;
        // Bump before choosing the side, so both sides of a surface see the same bumps.
        let ns = m.shading_normal(s.ns, s.ng, s.p);
        let (ng, ns) = if entering { (s.ng, ns) } else { (-s.ng, -ns) };
        let kd = m.diffuse.eval(s.p, s.uv);
        let mut l = m.emission + self.scene.settings().ambient * kd;
        if self.effects.shadows && m.is_lit() {
            l += self.direct(m, kd, s, ng, ns, wo, counts);
        }
        if depth >= self.max_depth {
            return l;
        }
        let dir = ray.dir.normalize();
        let mut mirror_weight = m.reflectivity;
        if self.effects.refraction && m.transmits() {
            let eta = if entering {
                self.medium_ior / m.ior
            } else {
                m.ior / self.medium_ior
            };
            let fresnel = fresnel_dielectric(-dir.dot(ns), eta);
            mirror_weight += m.transmission * fresnel;
            let w = m.transmission * (1.0 - fresnel);
            if let Some(t) = refract(dir, ns, eta).filter(|_| fresnel < 1.0)
                && self.keep_branch(weight * w, counts)
            {
                counts.refraction += 1;
                let r = Ray::new(s.spawn_origin(t, self.offset), t);
                l += w * self.trace(&r, depth + 1, weight * w, counts);
            }
        }
        if self.effects.reflection
            && mirror_weight > 0.0
            && self.keep_branch(weight * mirror_weight, counts)
        {
            counts.reflection += 1;
            let d = reflect(dir, ns);
            let r = Ray::new(s.spawn_origin(d, self.offset), d);
            l += mirror_weight * self.trace(&r, depth + 1, weight * mirror_weight, counts);
        }
        l
    }

    /// Lambert + Phong from every light that a shadow ray finds unoccluded.
    #[allow(clippy::too_many_arguments)]
    fn direct(
        &self,
        m: &Material,
        kd: Vec3,
        s: &SurfacePoint,
        ng: Vec3,
        ns: Vec3,
        wo: Vec3,
        counts: &mut RayCounts,
    ) -> Vec3 {
        let mut l = Vec3::ZERO;
        for light in self.scene.lights() {
            let ls = light.sample(s.p);
            let cos = ns.dot(ls.wi);
            // Lights behind the shading normal or below the geometric surface contribute nothing.
            if cos <= 0.0 || ng.dot(ls.wi) <= 0.0 {
                continue;
            }
            let origin = s.spawn_origin(ls.wi, self.offset);
            // Stop just short of a point light so the light's own position never counts as a blocker.
            let t_max = if ls.distance.is_finite() {
                ls.distance * (1.0 - 1e-4)
            } else {
                f32::INFINITY
            };
            counts.shadow += 1;
            if self.scene.occluded(
                self.accel,
                &Ray::segment(origin, ls.wi, t_max),
                &mut counts.traversal,
            ) {
                continue;
            }
            let mut f = kd * std::f32::consts::FRAC_1_PI;
            if m.shininess > 0.0 && m.specular != Vec3::ZERO {
                let cos_r = reflect(-ls.wi, ns).dot(wo).max(0.0);
                f += m.specular
                    * ((m.shininess + 2.0) * 0.5 * std::f32::consts::FRAC_1_PI)
                    * cos_r.powf(m.shininess);
            }
            l += f * ls.irradiance * cos;
        }
        l
    }
}
