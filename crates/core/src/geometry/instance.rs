//! Instances: one prototype (meshes and spheres with a hierarchy of their own, built once)
//! placed many times by affine transforms, as Embree, OptiX, Mitsuba and Cycles trace them.
//!
//! An instance is one primitive of the scene's top level. Its test moves the ray into the
//! prototype's object space and asks the prototype's own accelerator:
//!
//! 1. The ray is first *framed* for the instance ([`RayFrame`] over the instance's world box):
//!    an origin far from the instance (a camera 10 units from an instance scaled by 1e-6) is
//!    moved along the ray, in double-double, to near the instance, so the object-space origin
//!    is not rounded at a scale the prototype cannot resolve.
//! 2. Origin and direction are transformed by the inverse placement in `f64` and rounded to
//!    `f32` once each: the ray tested is the exact object-space image of the framed world ray,
//!    to half an `f32` ulp of each coordinate. The parameter `t` is the same in both spaces (an
//!    affine map keeps `o + t d` on the image of the line at the same `t`; the direction is not
//!    normalised), so hits of different instances and of the top level compare by `t` directly.
//! 3. A hit counts only where the framed world ray is inside the instance's world box as the
//!    traversals' slab tests compute it (the box is grown by the transform's rounding, so true
//!    hits are never near its edge): every box around the instance is then entered at that `t`
//!    too, and every accelerator finds exactly what brute force over instances finds.
//!
//! Surfaces are computed in object space and mapped back: points by the placement in `f64`
//! (the error bound carried through it), normals by the inverse transpose and normalised, so a
//! mirrored instance's faces point as the flattened mesh's do (whose winding the flattening
//! swaps). Tangents go by the placement with their handedness flipped under a mirror.

use std::sync::Arc;

use super::frame::{Framing, RayFrame};
use super::placement::Placement;
use super::{
    Contact, Geometry, HitAttributes, Precision, PrimHit, Primitive, SurfacePoint, Touch,
    WatertightRay,
};
use crate::math::{Aabb, Ray, Vec3};

/// What instances place: shapes with a hierarchy of their own, built once and shared by every
/// placement. The geometry sees a prototype only through these queries (the hierarchies are
/// the accelerators' business, above the geometry: `crate::instancing` builds them).
pub trait PrototypeQueries: std::fmt::Debug + Send + Sync {
    /// The shapes, in object space (their primitive indices are [`PrimHit::inner`]).
    fn geometry(&self) -> &Geometry;
    /// Bounds of the shapes.
    fn bounds(&self) -> Aabb;
    /// The nearest hit of object-space `ray` with the tests of `precision`: `t` on `ray`,
    /// barycentrics, and the primitive in `inner`.
    fn nearest(&self, ray: &Ray, precision: Precision) -> Option<PrimHit>;
    /// Whether something blocks object-space `ray`.
    fn blocks(&self, ray: &Ray, precision: Precision) -> bool;
    /// Every crossing and graze of object-space `ray` (the all-hits query, seams resolved
    /// inside the prototype): `t` on `ray`, the primitive in `inner`, and the graze flag.
    fn all_hits(&self, ray: &Ray, precision: Precision) -> Vec<(PrimHit, bool)>;
    /// Bytes of the shapes and the hierarchy (held once however many instances place them).
    fn bytes(&self) -> usize;
    /// The hierarchy over the shapes, opaque here (the accelerators know its type): a walk
    /// that enters instances in place walks it itself instead of calling [`Self::nearest`].
    fn hierarchy(&self) -> &dyn std::any::Any;
    /// The concrete prototype, for the module that builds them.
    fn as_any(&self) -> &dyn std::any::Any;
}

/// One placement of a prototype.
#[derive(Clone, Debug)]
pub struct Instance {
    /// Index into [`Geometry::prototypes`].
    pub prototype: u32,
    /// Where it is.
    pub placement: Placement,
    /// Its world box (see [`Placement::world_bounds`]).
    pub bounds: Aabb,
    /// Where rays are traced from into it (far origins are moved near it first).
    pub(super) frame: RayFrame,
}

impl Geometry {
    /// Whether primitive `index` blocks `ray` with the test `precision` selects: the verdict
    /// of [`Geometry::intersect_with`], by an any-hit query inside an instance.
    #[inline]
    pub fn blocks(&self, precision: Precision, index: u32, ray: &Ray, wr: &WatertightRay) -> bool {
        match self.prims[index as usize] {
            Primitive::Instance { instance } => self.instance_blocks(instance, ray, precision),
            _ => self.intersect_with(precision, index, ray, wr).is_some(),
        }
    }

    /// [`Geometry::intersect`] of a sphere or an instance, which need no shear.
    #[inline]
    pub(crate) fn intersect_alone(&self, index: u32, ray: &Ray) -> Option<PrimHit> {
        match self.prims[index as usize] {
            Primitive::Instance { instance } => {
                self.intersect_instance(instance, ray, Precision::Watertight)
            }
            Primitive::Sphere { sphere } => {
                self.spheres[sphere as usize]
                    .intersect(ray)
                    .map(|t| PrimHit {
                        t,
                        u: 0.0,
                        v: 0.0,
                        inner: 0,
                    })
            }
            // Not called for triangles (they go with their leaf's shear); answered all the same.
            Primitive::Triangle { .. } => self.intersect(index, ray, &WatertightRay::new(ray.dir)),
        }
    }

    /// [`Geometry::blocks`] of a sphere or an instance with the watertight tests.
    #[inline]
    pub(crate) fn blocks_alone(&self, index: u32, ray: &Ray) -> bool {
        match self.prims[index as usize] {
            Primitive::Instance { instance } => {
                self.instance_blocks(instance, ray, Precision::Watertight)
            }
            _ => self.intersect_alone(index, ray).is_some(),
        }
    }

    /// Adds a prototype; returns its index for [`Geometry::add_instance`].
    pub fn add_prototype(&mut self, prototype: Arc<dyn PrototypeQueries>) -> u32 {
        self.prototypes.push(prototype);
        self.prototypes.len() as u32 - 1
    }

    /// Places prototype `prototype` (must exist) by `placement`; returns its primitive index.
    pub fn add_instance(&mut self, prototype: u32, placement: Placement) -> u32 {
        let proto = &self.prototypes[prototype as usize];
        let bounds = placement.world_bounds(&proto.bounds());
        self.any_instances = true;
        self.instances.push(Instance {
            prototype,
            placement,
            bounds,
            frame: RayFrame::new(bounds),
        });
        self.prims.push(Primitive::Instance {
            instance: self.instances.len() as u32 - 1,
        });
        self.prims.len() as u32 - 1
    }

    /// The prototypes instances place.
    pub fn prototypes(&self) -> &[Arc<dyn PrototypeQueries>] {
        &self.prototypes
    }

    /// The prototypes, to rebuild their hierarchies (`crate::instancing`).
    pub(crate) fn prototypes_mut(&mut self) -> &mut [Arc<dyn PrototypeQueries>] {
        &mut self.prototypes
    }

    /// The instances, by instance index.
    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// True when some primitive is an instance.
    #[inline(always)]
    pub fn has_instances(&self) -> bool {
        self.any_instances
    }

    /// The instance primitive `index` is, if it is one.
    #[inline]
    pub fn instance_of(&self, index: u32) -> Option<u32> {
        // The flag first: scenes without instances never read the primitive list here.
        if !self.any_instances {
            return None;
        }
        match self.prims[index as usize] {
            Primitive::Instance { instance } => Some(instance),
            _ => None,
        }
    }

    /// The instance's framing of `ray` and the object-space ray to test. A ray traced as given
    /// is clipped to the interval in which it is inside the instance's box as the traversals
    /// compute it: every hit the prototype then reports lies in that box (see the module docs),
    /// and nearest and any-hit queries search the same interval.
    #[inline(always)]
    fn instance_ray(&self, instance: u32, ray: &Ray) -> Option<(&Instance, Framing, Ray)> {
        let inst = &self.instances[instance as usize];
        let framing = inst.frame.frame(ray);
        let object = match framing {
            Framing::AsGiven => Self::clipped_object_ray(inst, ray)?,
            _ => inst.placement.object_ray(framing.ray(ray)?)?,
        };
        Some((inst, framing, object))
    }

    /// [`Geometry::instance_ray`] of a ray the instance traces as given (its origin near
    /// the instance): the prototype and the object-space ray, on which a hit's `t` is the
    /// caller's and always counts; `Ok(None)` when nothing in the box can be hit. `Err` for a
    /// ray from far away, which the instance frames first (its nested query does).
    #[inline(always)]
    pub(crate) fn instance_ray_as_given(
        &self,
        instance: u32,
        ray: &Ray,
    ) -> Result<Option<(u32, Ray)>, ()> {
        let inst = &self.instances[instance as usize];
        if !inst.frame.holds(ray.origin) {
            return Err(());
        }
        Ok(Self::clipped_object_ray(inst, ray).map(|object| (inst.prototype, object)))
    }

    /// The object-space image of `ray` clipped to the interval in which it is inside `inst`'s
    /// box as the traversals compute it.
    #[inline(always)]
    fn clipped_object_ray(inst: &Instance, ray: &Ray) -> Option<Ray> {
        let (near, far) = crate::math::slab::box_range_inline(&inst.bounds, ray)?;
        let clipped = Ray {
            t_min: ray.t_min.max(near.next_down()),
            t_max: ray.t_max.min(far),
            ..*ray
        };
        // Empty, or NaN from a degenerate range: nothing in the box to find.
        if clipped.t_min.partial_cmp(&clipped.t_max) != Some(std::cmp::Ordering::Less) {
            return None;
        }
        inst.placement.object_ray(&clipped)
    }

    /// Whether hit distance `t` (on `ray`) counts for instance `inst` framed by `framing`: a
    /// clipped ray's hits always do; a moved ray's must lie in the box (see the module docs).
    #[inline(always)]
    fn in_instance_box(inst: &Instance, framing: &Framing, ray: &Ray, t: f32) -> bool {
        matches!(framing, Framing::AsGiven) || crate::math::slab::within_box(&inst.bounds, ray, t)
    }

    /// The nearest hit of `ray` on instance `instance` with the tests of `precision`: its `t`
    /// on `ray`, the prototype's barycentrics and, in [`PrimHit::inner`], the prototype's
    /// primitive.
    #[inline(never)]
    pub(crate) fn intersect_instance(
        &self,
        instance: u32,
        ray: &Ray,
        precision: Precision,
    ) -> Option<PrimHit> {
        let (inst, framing, object) = self.instance_ray(instance, ray)?;
        let found = self.prototypes[inst.prototype as usize].nearest(&object, precision)?;
        let t = framing.caller_t(found.t)?;
        Self::in_instance_box(inst, &framing, ray, t).then_some(PrimHit { t, ..found })
    }

    /// Whether something of instance `instance` blocks `ray`: the prototype's any-hit query
    /// over the clipped interval (the verdict of [`Geometry::intersect_instance`], found
    /// without looking for the nearest); a moved ray asks for the nearest hit.
    #[inline(never)]
    pub(crate) fn instance_blocks(&self, instance: u32, ray: &Ray, precision: Precision) -> bool {
        let Some((inst, framing, object)) = self.instance_ray(instance, ray) else {
            return false;
        };
        if !matches!(framing, Framing::AsGiven) {
            return self.intersect_instance(instance, ray, precision).is_some();
        }
        self.prototypes[inst.prototype as usize].blocks(&object, precision)
    }

    /// The contacts of `ray` with instance `instance` for an all-hits query: the prototype's
    /// own all-hits answer (its seams resolved inside it), as crossings and grazes.
    pub(super) fn instance_contacts(
        &self,
        instance: u32,
        index: u32,
        ray: &Ray,
        precision: Precision,
        out: &mut Vec<Contact>,
    ) {
        let Some((inst, framing, object)) = self.instance_ray(instance, ray) else {
            return;
        };
        let found = self.prototypes[inst.prototype as usize].all_hits(&object, precision);
        for (h, graze) in found {
            let Some(t) = framing.caller_t(h.t) else {
                continue;
            };
            if !Self::in_instance_box(inst, &framing, ray, t) {
                continue;
            }
            out.push(Contact {
                prim: index,
                hit: PrimHit { t, ..h },
                touch: if graze { Touch::Graze } else { Touch::Crossing },
            });
        }
    }

    /// The object-space ray and hit of a hit on instance `instance` found on `ray`.
    fn object_hit(&self, instance: u32, ray: &Ray, hit: &PrimHit) -> (&Instance, Ray, PrimHit) {
        let inst = &self.instances[instance as usize];
        let framing = inst.frame.frame(ray);
        let local = framing.ray(ray).copied().unwrap_or(*ray);
        let object = inst.placement.object_ray(&local).unwrap_or(local);
        let t = framing.local_t(hit.t);
        (inst, object, PrimHit { t, ..*hit })
    }

    /// [`Geometry::surface`] of a hit on an instance: computed in object space, mapped back.
    pub(super) fn instance_surface(
        &self,
        instance: u32,
        ray: &Ray,
        hit: &PrimHit,
        with_uv: bool,
    ) -> SurfacePoint {
        let (inst, object, h) = self.object_hit(instance, ray, hit);
        let proto = &self.prototypes[inst.prototype as usize];
        let s = proto.geometry().surface(hit.inner, &object, &h, with_uv);
        let (p, p_error) = inst.placement.world_point(s.p, s.p_error);
        let ng = inst.placement.world_normal(s.ng);
        let ns = inst.placement.world_normal(s.ns);
        SurfacePoint {
            p,
            ng,
            ns: if ns.dot(ng) < 0.0 { -ns } else { ns },
            p_error,
            ..s
        }
    }

    /// [`Geometry::geometric_normal`] of a hit on an instance.
    pub(super) fn instance_normal(&self, instance: u32, ray: &Ray, hit: &PrimHit) -> Vec3 {
        let (inst, object, h) = self.object_hit(instance, ray, hit);
        let proto = &self.prototypes[inst.prototype as usize];
        let n = proto.geometry().geometric_normal(hit.inner, &object, &h);
        inst.placement.world_normal(n)
    }

    /// [`Geometry::hit_attributes`] of a hit on an instance (tangents mapped to world space).
    pub(super) fn instance_attributes(
        &self,
        instance: u32,
        inner: u32,
        s: &SurfacePoint,
    ) -> HitAttributes {
        let inst = &self.instances[instance as usize];
        let proto = &self.prototypes[inst.prototype as usize];
        let mut a = proto.geometry().hit_attributes(inner, 0, s);
        a.tangent = a.tangent.map(|t| inst.placement.world_tangent(t));
        a
    }

    /// The primitive kind at the bottom of a hit: the prototype's primitive for an instance.
    pub fn leaf_primitive(&self, index: u32, inner: u32) -> Primitive {
        match self.prims[index as usize] {
            Primitive::Instance { instance } => {
                let proto = &self.prototypes[self.instances[instance as usize].prototype as usize];
                proto.geometry().prims[inner as usize]
            }
            p => p,
        }
    }
}
