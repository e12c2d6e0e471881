//! A top level of one instance: the scene is one placement of a prototype (a model loaded as
//! one instance, `lumis-lab instances-one --count 1`, `bench_embree --lumis-instance`). Its
//! hierarchy would be one leaf holding that instance, so every query would walk a root and a
//! leaf only to make the instance's own query; instead each query makes that query at once
//! (the world ray framed as the top level frames it, clipped to the instance's box and carried
//! into object space), and batches and camera packets of object-space rays go to the
//! prototype's own batch walk and packet walk. OptiX's single-GAS traversable graphs skip the
//! instance level the same way.
//!
//! The answers are the instance's nested query's ([`crate::geometry::PrototypeQueries`]), which
//! the one-leaf walk would have made for every ray whose hits it could find: that query only
//! reports hits inside the instance's box, which the root's box holds. So they equal brute
//! force over instances bit for bit (`tests/it/instances/one_instance.rs`).

mod batch;

use super::{Accel, Hit, PACKET, PrimHit, Traced, TraversalStats};
use crate::geometry::{Geometry, Precision, Primitive};
use crate::math::{Ray, Vec3};

/// The one primitive of a top level made of one instance, and that instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct OnlyInstance {
    prim: u32,
    instance: u32,
}

impl OnlyInstance {
    /// The instance `geometry` is made of, if it is one instance and nothing else.
    pub(super) fn of(geometry: &Geometry) -> Option<Self> {
        match geometry.prims() {
            [Primitive::Instance { instance }] => Some(Self {
                prim: 0,
                instance: *instance,
            }),
            _ => None,
        }
    }

    /// The prototype's accelerator and shapes; `None` for a prototype without an [`Accel`].
    #[inline(always)]
    fn prototype(self, geometry: &Geometry) -> Option<(&Accel, &Geometry)> {
        let instance = geometry.instances().get(self.instance as usize)?;
        let proto = &geometry.prototypes()[instance.prototype as usize];
        let accel = proto.hierarchy().downcast_ref::<Accel>()?;
        Some((accel, proto.geometry()))
    }

    /// The object-space image of `ray` clipped to the instance's box: `Ok(None)` when nothing
    /// in the box can be hit, `Err` when the instance frames the ray first (from far away).
    #[inline(always)]
    fn object_ray(self, geometry: &Geometry, ray: &Ray) -> Result<Option<Ray>, ()> {
        Ok(geometry
            .instance_ray_as_given(self.instance, ray)?
            .map(|(_, object)| object))
    }

    /// The prototype's answer `found` (on an object-space ray traced as given) as the hit of
    /// this instance on world ray `ray`: the same `t`, the prototype's primitive in `inner`,
    /// the slot in the prototype's packed leaves.
    #[inline(always)]
    fn traced_on(self, ray: &Ray, found: Traced) -> Traced {
        let hit = Hit {
            prim: self.prim,
            hit: PrimHit {
                t: found.t,
                inner: found.hit.prim,
                ..found.hit.hit
            },
        };
        Traced::on(ray, (hit, found.slot), found.t)
    }

    /// The nearest hit of `ray` (framed by the top level) and its slot in the prototype's
    /// packed leaves when it was found there. Out of line: the queries of every other scene
    /// keep their inlined walks (`trace_packet` grew past inlining with this in it: +0.8%
    /// instructions per render of a flat mesh).
    #[inline(never)]
    pub(super) fn nearest(
        self,
        geometry: &Geometry,
        precision: Precision,
        ray: &Ray,
        stats: &mut TraversalStats,
    ) -> Option<(Hit, Option<u32>)> {
        let (accel, shapes) = match self.prototype(geometry) {
            Some(p) => p,
            None => return self.nested(geometry, precision, ray),
        };
        match self.object_ray(geometry, ray) {
            Ok(None) => None,
            Ok(Some(object)) => {
                let found = accel.trace_geometry(shapes, precision, &object, stats)?;
                let traced = self.traced_on(ray, found);
                Some((traced.hit, traced.slot))
            }
            Err(()) => self.nested(geometry, precision, ray),
        }
    }

    /// The instance's nested query, as the top level's leaf makes it.
    #[cold]
    fn nested(
        self,
        geometry: &Geometry,
        precision: Precision,
        ray: &Ray,
    ) -> Option<(Hit, Option<u32>)> {
        let hit = geometry.intersect_instance(self.instance, ray, precision)?;
        Some((
            Hit {
                prim: self.prim,
                hit,
            },
            None,
        ))
    }

    /// Whether something of the instance blocks `ray` (framed by the top level).
    #[inline(always)]
    pub(super) fn blocks(self, geometry: &Geometry, precision: Precision, ray: &Ray) -> bool {
        geometry.instance_blocks(self.instance, ray, precision)
    }
}

impl Accel {
    /// The instance this accelerator's scene is made of, when its queries go straight to it.
    #[inline(always)]
    pub(super) fn only_instance(&self) -> Option<OnlyInstance> {
        self.only_instance
    }

    /// Marks the scene of `geometry` as one instance when it is one and this is the wide
    /// hierarchy walked in order (the paper's structures and traversals keep their walks, to
    /// be measured as they are). Its packed leaves (none: an instance is not a triangle) are
    /// dropped, so that every query of such a scene leaves the packed paths at their first
    /// test and finds the instance among the fallbacks: the queries of all other scenes keep
    /// their code as it was.
    pub(super) fn note_only_instance(&mut self, geometry: &Geometry) {
        self.only_instance = OnlyInstance::of(geometry).filter(|_| self.packed().is_some());
        if self.only_instance.is_some() {
            self.packed = None;
        }
    }

    /// [`Accel::trace_packet`] of a scene of one instance: the packet's object-space rays as
    /// one packet of the prototype (they share an origin as the world rays do); rays that
    /// miss the instance's box ride along with an empty interval. `false` as `trace_packet`,
    /// and for any other scene without packed leaves.
    #[cold]
    #[inline(never)]
    pub(super) fn trace_packet_in_only_instance(
        &self,
        geometry: &Geometry,
        rays: &[Ray],
        stats: &mut TraversalStats,
        out: &mut [Option<Traced>],
    ) -> bool {
        let Some(only) = self.only_instance else {
            return false;
        };
        if rays.len() > PACKET || !rays.iter().all(|r| self.frame.holds(r.origin)) {
            return false;
        }
        let Some((accel, shapes)) = only.prototype(geometry) else {
            return false;
        };
        // The object-space rays in place (a packet is often one ray: no arrays of options).
        let n = rays.len();
        let mut objects = [Ray::new(Vec3::ZERO, Vec3::X); PACKET];
        let mut live = 0u32;
        for (k, ray) in rays.iter().enumerate() {
            match only.object_ray(geometry, ray) {
                Ok(Some(object)) => {
                    objects[k] = object;
                    live |= 1 << k;
                }
                Ok(None) => {}
                Err(()) => return false,
            }
        }
        if live == 0 {
            out[..n].fill(None);
            return true;
        }
        let first = objects[live.trailing_zeros() as usize];
        for (k, o) in objects[..n].iter_mut().enumerate() {
            if live & (1 << k) == 0 {
                *o = Ray {
                    t_max: first.t_min,
                    ..first
                };
            }
        }
        // Written only when the packet is walked (a refused one writes nothing).
        if !accel.trace_packet(
            shapes,
            Precision::Watertight,
            &objects[..n],
            stats,
            &mut out[..n],
        ) {
            return false;
        }
        for (k, (o, ray)) in out[..n].iter_mut().zip(rays).enumerate() {
            *o = if live & (1 << k) != 0 {
                o.map(|f| only.traced_on(ray, f))
            } else {
                None
            };
        }
        true
    }
}
