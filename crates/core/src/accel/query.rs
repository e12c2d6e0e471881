//! The queries every accelerator answers: nearest hit and any hit, through a closure per
//! primitive or through the scene's own primitive tests. Each one first asks the accelerator's
//! [`RayFrame`] how the ray is traced: as given, or from near the scene when its origin lies
//! far away (the hit's `t` is then mapped back to the caller's ray), or not at all.

use super::PackedWatertight;
use super::batch_queries::PackedQueries;
use super::{Accel, Hit, PACKET, PrimHit, Structure, Traversal, TraversalStats, leaves};
use crate::geometry::{Geometry, Precision, with_prim_test};
use crate::math::Ray;

/// A nearest hit with the ray it was found on: the caller's ray, or the ray moved to near
/// the scene when its origin lay far away ([`RayFrame`]). Surfaces are computed on that ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Traced {
    /// The hit, its `t` measured on [`Traced::ray`].
    pub hit: Hit,
    /// The ray traced, `t_max` shrunk to the hit.
    pub ray: Ray,
    /// The hit's `t` on the caller's ray.
    pub t: f32,
    /// Where the hit triangle lies in the packed leaves, when it was found there
    /// ([`Accel::packed_corners`] reads its corners); `None` otherwise (and for spheres).
    pub slot: Option<u32>,
}

impl Traced {
    /// A hit found on `ray`, whose caller's `t` is `t`.
    #[inline(always)]
    pub(super) fn on(ray: &Ray, (hit, slot): (Hit, Option<u32>), t: f32) -> Self {
        Self {
            hit,
            ray: Ray {
                t_max: hit.hit.t,
                ..*ray
            },
            t,
            slot,
        }
    }

    /// The hit with the caller's `t`: what brute force and every accelerator report.
    pub fn caller_hit(&self) -> Hit {
        Hit {
            prim: self.hit.prim,
            hit: PrimHit {
                t: self.t,
                ..self.hit.hit
            },
        }
    }
}

impl Accel {
    /// The nearest hit of `ray` among the primitives of `geometry` (the geometry this was
    /// built for) with the primitive tests of `precision`: through the packed leaves when
    /// there are any and the tests are the watertight ones, else one primitive at a time.
    #[inline]
    pub fn intersect_geometry(
        &self,
        geometry: &Geometry,
        precision: Precision,
        ray: &Ray,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        self.trace_geometry(geometry, precision, ray, stats)
            .map(|t| t.caller_hit())
    }

    /// [`Accel::intersect_geometry`], with the ray the hit was found on (see [`Traced`]).
    #[inline]
    pub fn trace_geometry(
        &self,
        geometry: &Geometry,
        precision: Precision,
        ray: &Ray,
        stats: &mut TraversalStats,
    ) -> Option<Traced> {
        if self.frame.holds(ray.origin) {
            let found = self.nearest_in_geometry(geometry, precision, ray, stats)?;
            return Some(Traced::on(ray, found, found.0.hit.t));
        }
        self.trace_far(geometry, precision, ray, stats)
    }

    /// [`Accel::trace_geometry`] of up to [`PACKET`] rays at once, walked together (see
    /// `wide::packet`): each ray's answer into `out`, bit for bit what `trace_geometry` gives
    /// it. `false`, with nothing written, when the rays cannot share a walk (other origins, the
    /// far-away framing, another precision or structure): trace them one at a time.
    #[inline(always)]
    pub fn trace_packet(
        &self,
        geometry: &Geometry,
        precision: Precision,
        rays: &[Ray],
        stats: &mut TraversalStats,
        out: &mut [Option<Traced>],
    ) -> bool {
        let (Precision::Watertight, Some((wide, packed))) = (precision, self.packed()) else {
            return precision == Precision::Watertight
                && self.trace_packet_in_only_instance(geometry, rays, stats, out);
        };
        if rays.len() > PACKET || !rays.iter().all(|r| self.frame.holds(r.origin)) {
            return false;
        }
        let mut testers: [PackedWatertight; PACKET] =
            std::array::from_fn(|_| PackedWatertight::new(packed, geometry));
        let mut hits = [None; PACKET];
        if !wide.intersect_packet(rays, stats, &mut testers, &mut hits[..rays.len()]) {
            return false;
        }
        for ((o, hit), (ray, tester)) in out.iter_mut().zip(&hits).zip(rays.iter().zip(&testers)) {
            let slot = tester.best_slot();
            *o = hit.map(|h| Traced::on(ray, (h, slot), h.hit.t));
        }
        true
    }

    /// [`Accel::trace_geometry`] of every ray `rays` yields, each answer given to `answer`
    /// with the ray's id, with up to `K` rays walked at once on this thread (see
    /// `wide::in_flight`; `K = 1`: one at a time). The answers are those of
    /// [`Accel::trace_geometry`], bit for bit, in the order the rays finish.
    pub fn trace_geometry_each<const K: usize, Id: Copy>(
        &self,
        geometry: &Geometry,
        precision: Precision,
        stats: &mut TraversalStats,
        rays: impl FnMut() -> Option<(Id, Ray)>,
        answer: impl FnMut(Id, Option<Traced>),
    ) {
        if let (Precision::Watertight, Some(only), true) = (precision, self.only_instance(), K > 1)
        {
            return self.trace_each_in_only_instance::<K, _>(only, geometry, stats, rays, answer);
        }
        self.trace_each_walked::<K, _>(geometry, precision, stats, rays, answer)
    }

    /// [`Accel::trace_geometry_each`] through this accelerator's own walk.
    pub(super) fn trace_each_walked<const K: usize, Id: Copy>(
        &self,
        geometry: &Geometry,
        precision: Precision,
        stats: &mut TraversalStats,
        mut rays: impl FnMut() -> Option<(Id, Ray)>,
        mut answer: impl FnMut(Id, Option<Traced>),
    ) {
        if let (Precision::Watertight, Some((wide, packed)), true) =
            (precision, self.packed(), K > 1)
        {
            let parts = (self, geometry, packed);
            if geometry.has_instances() {
                let mut queries = PackedQueries::<_, _, true>::new(parts, rays, answer);
                return wide.intersect_in_flight::<K, _>(&mut queries, stats);
            }
            let mut queries = PackedQueries::<_, _, false>::new(parts, rays, answer);
            return wide.intersect_in_flight::<K, _>(&mut queries, stats);
        }
        while let Some((id, ray)) = rays() {
            answer(id, self.trace_geometry(geometry, precision, &ray, stats));
        }
    }

    /// [`Accel::trace_geometry`] of a ray from outside the near region.
    #[cold]
    #[inline(never)]
    pub(super) fn trace_far(
        &self,
        geometry: &Geometry,
        precision: Precision,
        ray: &Ray,
        stats: &mut TraversalStats,
    ) -> Option<Traced> {
        let framing = self.frame.frame(ray);
        let local = framing.ray(ray)?;
        let found = self.nearest_in_geometry(geometry, precision, local, stats)?;
        let t = framing.caller_t(found.0.hit.t)?;
        Some(Traced::on(local, found, t))
    }

    /// The nearest hit, and its slot in the packed leaves when it was found there.
    #[inline(always)]
    fn nearest_in_geometry(
        &self,
        geometry: &Geometry,
        precision: Precision,
        ray: &Ray,
        stats: &mut TraversalStats,
    ) -> Option<(Hit, Option<u32>)> {
        if let (Precision::Watertight, Some((wide, packed))) = (precision, self.packed()) {
            let mut test = PackedWatertight::new(packed, geometry);
            let hit = wide.intersect(ray, stats, &mut test)?;
            return Some((hit, test.best_slot()));
        }
        if let Some(only) = self.only_instance() {
            return only.nearest(geometry, precision, ray, stats);
        }
        // One traversal instantiation per precision, chosen once per ray.
        let hit = with_prim_test!(geometry, precision, ray, |test| self
            .nearest(ray, stats, test))?;
        Some((hit, None))
    }

    /// True when a primitive of `geometry` blocks `ray` (see [`Accel::intersect_geometry`]).
    #[inline]
    pub fn occluded_geometry(
        &self,
        geometry: &Geometry,
        precision: Precision,
        ray: &Ray,
        stats: &mut TraversalStats,
    ) -> bool {
        if self.frame.holds(ray.origin) {
            return self.any_in_geometry(geometry, precision, ray, stats);
        }
        self.occluded_far(geometry, precision, ray, stats)
    }

    /// [`Accel::occluded_geometry`] of a ray from outside the near region.
    #[cold]
    #[inline(never)]
    fn occluded_far(
        &self,
        geometry: &Geometry,
        precision: Precision,
        ray: &Ray,
        stats: &mut TraversalStats,
    ) -> bool {
        let framing = self.frame.frame(ray);
        framing
            .ray(ray)
            .is_some_and(|local| self.any_in_geometry(geometry, precision, local, stats))
    }

    #[inline(always)]
    fn any_in_geometry(
        &self,
        geometry: &Geometry,
        precision: Precision,
        ray: &Ray,
        stats: &mut TraversalStats,
    ) -> bool {
        if let (Precision::Watertight, Some((wide, packed))) = (precision, self.packed()) {
            return wide.occluded(ray, stats, PackedWatertight::for_any(packed, geometry));
        }
        if let Some(only) = self.only_instance() {
            return only.blocks(geometry, precision, ray);
        }
        if geometry.has_instances() {
            // Instances answer any-hit queries with their own any-hit walk.
            let wr = crate::geometry::WatertightRay::new(ray.dir);
            return self.any(ray, stats, |p, r| geometry.blocks(precision, p, r, &wr));
        }
        with_prim_test!(geometry, precision, ray, |test| {
            self.any(ray, stats, |p, r| test(p, r).is_some())
        })
    }

    /// The nearest hit of `ray` in `(t_min, t_max]`; `test(prim, ray)` intersects one primitive
    /// with a ray whose `t_max` has been shrunk to the best hit so far. A ray from far away is
    /// traced from near the scene ([`RayFrame`]): `test` then sees that ray, and the hit's `t`
    /// is mapped back to `ray`'s.
    #[inline]
    pub fn intersect<F>(&self, ray: &Ray, stats: &mut TraversalStats, test: F) -> Option<Hit>
    where
        F: FnMut(u32, &Ray) -> Option<PrimHit>,
    {
        if self.frame.holds(ray.origin) {
            return self.nearest(ray, stats, test);
        }
        let framing = self.frame.frame(ray);
        let h = self.nearest(framing.ray(ray)?, stats, test)?;
        Some(Hit {
            prim: h.prim,
            hit: PrimHit {
                t: framing.caller_t(h.hit.t)?,
                ..h.hit
            },
        })
    }

    /// True when anything blocks `ray` in `(t_min, t_max]`; stops at the first hit found.
    #[inline]
    pub fn occluded<F>(&self, ray: &Ray, stats: &mut TraversalStats, test: F) -> bool
    where
        F: FnMut(u32, &Ray) -> bool,
    {
        if self.frame.holds(ray.origin) {
            return self.any(ray, stats, test);
        }
        let framing = self.frame.frame(ray);
        framing
            .ray(ray)
            .is_some_and(|local| self.any(local, stats, test))
    }

    /// [`Accel::intersect`] of a ray traced as given.
    #[inline(always)]
    fn nearest<F>(&self, ray: &Ray, stats: &mut TraversalStats, test: F) -> Option<Hit>
    where
        F: FnMut(u32, &Ray) -> Option<PrimHit>,
    {
        match (&self.structure, &self.traversal) {
            (Structure::Brute(b), _) => b.intersect(ray, stats, test),
            // Only ever walked in order: `with_traversal` unfolds it for the others.
            (Structure::Wide(w), _) => w.intersect(ray, stats, &mut leaves::PerPrim(test)),
            (Structure::Bvh(b), Traversal::Ordered) => b.intersect(ray, stats, test),
            (Structure::Bvh(b), Traversal::Segments(p)) => {
                b.intersect_segments(ray, p, stats, test)
            }
            (Structure::Bvh(b), Traversal::Exhaustive) => b.intersect_exhaustive(ray, stats, test),
            #[cfg(feature = "paper-original-rule")]
            (Structure::Bvh(b), Traversal::SegmentsOriginalRule(p)) => {
                b.intersect_segments_original_rule(ray, p, stats, test)
            }
        }
    }

    /// [`Accel::occluded`] of a ray traced as given.
    #[inline(always)]
    pub(super) fn any<F>(&self, ray: &Ray, stats: &mut TraversalStats, test: F) -> bool
    where
        F: FnMut(u32, &Ray) -> bool,
    {
        match (&self.structure, &self.traversal) {
            (Structure::Brute(b), _) => b.occluded(ray, stats, test),
            (Structure::Wide(w), _) => w.occluded(ray, stats, leaves::PerPrim(test)),
            (Structure::Bvh(b), Traversal::Ordered | Traversal::Exhaustive) => {
                b.occluded(ray, stats, test)
            }
            (Structure::Bvh(b), Traversal::Segments(p)) => b.occluded_segments(ray, p, stats, test),
            #[cfg(feature = "paper-original-rule")]
            (Structure::Bvh(b), Traversal::SegmentsOriginalRule(p)) => {
                b.occluded_segments(ray, p, stats, test)
            }
        }
    }
}
