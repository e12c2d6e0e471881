//! Whitted-style ray tracing: direct light with hard shadows, recursive mirror reflection and
//! Fresnel-weighted refraction, up to `max_depth` bounces.
//!
//! Every ray is traced only where its result can change the image (see [`crate::effects`]).
//! The shading code is one generic function over `ALL`: with `ALL = true` (the
//! `--effects all` reference) every skip test is compiled out and every ray kind is traced;
//! with `ALL = false` a ray is skipped only where the reference multiplies its result by an
//! exact zero, so both produce the same bits. It is generic over `SPLIT` too: the camera
//! ray's first hit, when the light-path passes are asked for, also writes its terms into a
//! [`Split`] (`paths.rs`); every other instance has no trace of those tests.

use super::RayCounts;
use super::paths::Split;
use crate::effects::{Analysis, EffectMode, MaterialTraits};
use crate::environment::Environment;
use crate::geometry::{Offset, SurfacePoint};
use crate::light::LightSample;
use crate::material::{Material, fresnel_dielectric, reflect, refract};
use crate::math::{Ray, Vec3};
use crate::scene::limits::MAX_SAMPLE_RADIANCE;
use crate::scene::{Interaction, Scene, World};

/// The Whitted integrator over one world (a scene and its accelerator); its camera-ray entry
/// points are in `camera.rs`.
pub struct Whitted<'a> {
    pub(super) world: &'a World,
    pub(super) scene: &'a Scene,
    pub(super) analysis: &'a Analysis,
    pub(super) all: bool,
    max_depth: u32,
    medium_ior: f32,
    pub(super) offset: Offset,
    cutoff: f32,
    /// What escaping rays see and where ambient light comes from; `None`: the constant
    /// background and ambient of the settings.
    pub(super) env: Option<&'a Environment>,
    /// Escaping camera rays add nothing (`--transparent`).
    pub(super) transparent: bool,
    /// Whether any material is a shadow catcher (else no hit is tested for one).
    pub(super) catchers: bool,
}

/// What the material of one hit is and can do.
struct Shading<'m> {
    m: &'m Material,
    traits: MaterialTraits,
}

impl<'a> Whitted<'a> {
    /// An integrator that traces what `analysis` (made for `world`'s scene) decided.
    pub fn new(world: &'a World, analysis: &'a Analysis) -> Self {
        let scene = world.scene();
        let st = scene.settings();
        Self {
            world,
            scene,
            analysis,
            all: analysis.mode == EffectMode::All,
            max_depth: st.max_depth,
            medium_ior: st.medium_ior,
            offset: st.offset,
            cutoff: st.cutoff,
            env: scene.environment(),
            transparent: false,
            catchers: scene.materials().iter().any(|m| m.shadow_catcher),
        }
    }

    /// The same integrator with escaping camera rays transparent (`--transparent`): they
    /// add no colour and no alpha; reflected and refracted rays still see the background.
    pub fn with_transparent(self, transparent: bool) -> Self {
        Self {
            transparent,
            ..self
        }
    }

    /// The world rays are traced through.
    pub fn world(&self) -> &'a World {
        self.world
    }

    /// Radiance along a secondary ray at bounce `depth`, whose radiance enters the pixel
    /// multiplied by `weight`. Shadow catchers are invisible to it (their shadows are for
    /// the plate, which reflections do not show): it goes on through them.
    #[inline]
    fn trace<const ALL: bool>(
        &self,
        ray: &Ray,
        depth: u32,
        weight: f32,
        counts: &mut RayCounts,
    ) -> Vec3 {
        match self.world.intersect(ray, &mut counts.traversal) {
            Some(hit) if self.catchers && self.is_catcher(&hit) => {
                self.trace_past_catchers::<ALL>(ray, &hit, depth, weight, counts)
            }
            Some(hit) => self.shade::<ALL, false>(ray, &hit, depth, weight, counts, None),
            None => self.background(ray.dir),
        }
    }

    /// [`Whitted::trace`] of `ray` from beyond the catcher it hit at `hit`, and past any
    /// further ones (at most [`MAX_CATCHER_CROSSINGS`]). Out of line: scenes without catchers
    /// never come here, and the common path stays small.
    #[cold]
    #[inline(never)]
    fn trace_past_catchers<const ALL: bool>(
        &self,
        ray: &Ray,
        hit: &Interaction,
        depth: u32,
        weight: f32,
        counts: &mut RayCounts,
    ) -> Vec3 {
        let mut ray = Ray::new(hit.surface.spawn_origin(ray.dir, self.offset), ray.dir);
        for _ in 0..MAX_CATCHER_CROSSINGS {
            match self.world.intersect(&ray, &mut counts.traversal) {
                Some(hit) if self.is_catcher(&hit) => {
                    ray = Ray::new(hit.surface.spawn_origin(ray.dir, self.offset), ray.dir);
                }
                Some(hit) => {
                    return self.shade::<ALL, false>(&ray, &hit, depth, weight, counts, None);
                }
                None => return self.background(ray.dir),
            }
        }
        self.background(ray.dir)
    }

    /// Whether the hit's object has a shadow-catcher material.
    #[inline]
    pub(super) fn is_catcher(&self, hit: &Interaction) -> bool {
        self.scene.material_of(hit.object).shadow_catcher
    }

    /// True when a branch whose radiance enters the pixel with weight `weight` (its own weight
    /// at this hit is `w`) is traced; otherwise counts why not in `skips`.
    fn keep_branch<const ALL: bool>(
        &self,
        w: f32,
        weight: f32,
        skips: &mut super::BranchSkips,
    ) -> bool {
        if ALL {
            return true;
        }
        if w <= 0.0 {
            skips.zero_weight += 1;
            return false;
        }
        let keep = weight >= self.cutoff;
        skips.cutoff += u64::from(!keep);
        keep
    }

    /// Radiance leaving `hit` back along `ray`; `weight` is the product of the reflection and
    /// transmission factors that brought the camera ray here.
    pub(super) fn shade<const ALL: bool, const SPLIT: bool>(
        &self,
        ray: &Ray,
        hit: &Interaction,
        depth: u32,
        weight: f32,
        counts: &mut RayCounts,
        mut split: Option<&mut Split>,
    ) -> Vec3 {
        let index = self.scene.objects()[hit.object as usize].material;
        let s = &hit.surface;
        let base = &self.scene.materials()[index as usize];
        // A textured material becomes the constant material that holds at this hit; the
        // traits stay the base material's, which bound every hit's.
        let at_hit = base.textured.as_ref().and_then(|_| {
            base.at_hit(
                &self.scene.geometry().hit_attributes(hit.prim, hit.inner, s),
                s.ns,
                s.ng,
            )
        });
        let (m, occlusion, ns) = match &at_hit {
            Some(a) => (&a.material, a.occlusion, a.ns),
            None => (base, 1.0, s.ns),
        };
        let sh = Shading {
            m,
            traits: self.analysis.material(index),
        };
        let wo = -ray.dir.normalize();
        // Shade the side the ray arrived on; `entering` tells refraction which way it goes.
        let entering = ray.dir.dot(s.ng) < 0.0;
        // Bump before choosing the side, so both sides of a surface see the same bumps.
        let ns = m.shading_normal(ns, s.ng, s.p);
        let (ng, ns) = if entering { (s.ng, ns) } else { (-s.ng, -ns) };
        let kd = m.diffuse.eval(s.p, s.uv);
        // Starting from +0 keeps every sum identical whether or not a zero term is added.
        let mut l = Vec3::ZERO;
        if ALL || sh.traits.emits {
            l += m.emission;
            if SPLIT && let Some(sp) = split.as_deref_mut() {
                sp.paths.emission = m.emission;
            }
        }
        let ambient = self.ambient(ns) * kd * occlusion;
        l += ambient;
        l += self.direct::<ALL, SPLIT>(&sh, kd, s, ng, ns, wo, counts, split.as_deref_mut());
        if SPLIT && let Some(sp) = split.as_deref_mut() {
            sp.paths.ambient = ambient;
        }
        if depth >= self.max_depth {
            return saturate(l);
        }
        let dir = ray.dir.normalize();
        let mut mirror_weight = m.reflectivity;
        if ALL || sh.traits.transmits {
            let eta = if entering {
                self.medium_ior / m.ior
            } else {
                m.ior / self.medium_ior
            };
            let fresnel = fresnel_dielectric(-dir.dot(ns), eta);
            mirror_weight += m.transmission * fresnel;
            let w = m.transmission * (1.0 - fresnel);
            match refract(dir, ns, eta) {
                // Total internal reflection: there is no refracted ray to trace.
                None => counts.not_traced.refraction.zero_weight += u64::from(!ALL),
                Some(t) => {
                    if self.keep_branch::<ALL>(w, weight * w, &mut counts.not_traced.refraction) {
                        counts.refraction += 1;
                        let r = Ray::new(s.spawn_origin(t, self.offset), t);
                        let through = w * self.trace::<ALL>(&r, depth + 1, weight * w, counts);
                        l += through;
                        if SPLIT && let Some(sp) = split.as_deref_mut() {
                            sp.paths.refraction = through;
                        }
                    }
                }
            }
        } else {
            counts.not_traced.refraction.material += 1;
        }
        if !ALL && !sh.traits.reflects {
            counts.not_traced.reflection.material += 1;
        } else if self.keep_branch::<ALL>(
            mirror_weight,
            weight * mirror_weight,
            &mut counts.not_traced.reflection,
        ) {
            counts.reflection += 1;
            let d = reflect(dir, ns);
            let r = Ray::new(s.spawn_origin(d, self.offset), d);
            let mirrored =
                mirror_weight * self.trace::<ALL>(&r, depth + 1, weight * mirror_weight, counts);
            l += mirrored;
            if SPLIT && let Some(sp) = split {
                sp.paths.reflection = mirrored;
            }
        }
        saturate(l)
    }

    /// Lambert + Phong from every light that a shadow ray finds unoccluded. A shadow ray is
    /// cast only when the light's unshadowed contribution is not exactly zero.
    #[allow(clippy::too_many_arguments)]
    fn direct<const ALL: bool, const SPLIT: bool>(
        &self,
        sh: &Shading,
        kd: Vec3,
        s: &SurfacePoint,
        ng: Vec3,
        ns: Vec3,
        wo: Vec3,
        counts: &mut RayCounts,
        mut split: Option<&mut Split>,
    ) -> Vec3 {
        let lights = self.scene.lights();
        if !ALL && !sh.traits.lit {
            counts.not_traced.shadow.material_unlit += lights.len() as u64;
            return Vec3::ZERO;
        }
        let mut l = Vec3::ZERO;
        for (index, (light, &reachable)) in lights
            .iter()
            .zip(&self.analysis.lights_reachable)
            .enumerate()
        {
            if !ALL && !reachable {
                counts.not_traced.shadow.dark_light += 1;
                continue;
            }
            let ls = light.sample(s.p);
            let c = self.unshadowed::<ALL>(sh, kd, ng, ns, wo, &ls);
            if !ALL && c == Vec3::ZERO {
                // Only the count depends on which zero it was; the skip itself needs none of this.
                let skips = &mut counts.not_traced.shadow;
                if ns.dot(ls.wi) <= 0.0 || ng.dot(ls.wi) <= 0.0 {
                    skips.back_facing += 1;
                } else if light.is_spot() && ls.irradiance == Vec3::ZERO {
                    skips.outside_cone += 1;
                } else {
                    skips.zero_contribution += 1;
                }
                continue;
            }
            if ls.wi == Vec3::ZERO {
                // A light exactly at the shaded point has no direction to trace (a zero
                // direction is outside the query domain, src/scene/domain.rs); `c` is 0 there
                // (cos = 0), so even the reference loses nothing by not tracing it.
                continue;
            }
            if self.sees_light(s, &ls, counts) {
                l += c;
                if SPLIT && let Some(sp) = split.as_deref_mut() {
                    let cos = ns.dot(ls.wi);
                    sp.paths.diffuse += kd * std::f32::consts::FRAC_1_PI * ls.irradiance * cos;
                    if ALL || sh.traits.phong {
                        sp.paths.specular += sh.m.phong(ls.wi, wo, ns) * ls.irradiance * cos;
                    }
                    sp.lights[index] = c;
                }
            }
        }
        l
    }

    /// Whether the light of sample `ls` reaches surface point `s`: one shadow ray, counted.
    /// It stops just short of a point light, so the light's own position never counts as a
    /// blocker. `ls.wi` must not be zero (a light at the point has no direction to trace).
    #[inline]
    pub(super) fn sees_light(
        &self,
        s: &SurfacePoint,
        ls: &LightSample,
        counts: &mut RayCounts,
    ) -> bool {
        let t_max = if ls.distance.is_finite() {
            ls.distance * (1.0 - 1e-4)
        } else {
            f32::INFINITY
        };
        counts.shadow += 1;
        let ray = Ray::segment(s.spawn_origin(ls.wi, self.offset), ls.wi, t_max);
        !self.world.occluded(&ray, &mut counts.traversal)
    }

    /// What light sample `ls` adds at a point if nothing blocks it. The Whitted BRDF reflects
    /// only: light from behind the shading normal or below the geometric surface adds nothing.
    #[inline(always)]
    fn unshadowed<const ALL: bool>(
        &self,
        sh: &Shading,
        kd: Vec3,
        ng: Vec3,
        ns: Vec3,
        wo: Vec3,
        ls: &LightSample,
    ) -> Vec3 {
        let cos = ns.dot(ls.wi);
        if cos <= 0.0 || ng.dot(ls.wi) <= 0.0 {
            return Vec3::ZERO;
        }
        let mut f = kd * std::f32::consts::FRAC_1_PI;
        if ALL || sh.traits.phong {
            f += sh.m.phong(ls.wi, wo, ns);
        }
        f * ls.irradiance * cos
    }
}

/// Most shadow catchers a secondary ray goes through before it is taken to escape (they are
/// ground planes and walls: a ray crosses few of them).
const MAX_CATCHER_CROSSINGS: u32 = 16;

/// `l` capped at [`MAX_SAMPLE_RADIANCE`]: every input is finite and bounded, but 64 bounces of
/// mirror weight up to 2 over many lights are not, and an infinite radiance times a zero weight
/// upstream would be a NaN pixel. Identical in both effect modes, so they still agree bit for bit.
#[inline]
fn saturate(l: Vec3) -> Vec3 {
    l.min(Vec3::splat(MAX_SAMPLE_RADIANCE))
}
