//! Triangles copied into the wide hierarchy's leaf order, four to a group, one SSE register
//! per vertex coordinate, so a leaf's triangles are tested without chasing mesh indices.
//!
//! A group's four triangles are decided together in SIMD ([`classify`]) with the scalar
//! watertight test's own operations: lanes whose edge signs disagree are rejected, lanes that
//! are clean hits on the triangle's line get their barycentrics there and need only the `f64`
//! plane distance and the range check ([`finish_decided_hit`]), and the rest (an edge within its
//! rounding bound, a determinant out of range, a sphere) go through [`intersect_triangle`]
//! whole. Every answer is the per-primitive path's, bit for bit.
//!
//! The ray's shear (three divisions) is set up at the first leaf the ray reaches, so rays that
//! miss every leaf never pay for it.

mod classify;
mod contacts;

use super::leaves::{AnyLeaves, ClosestLeaves, Prefetch, prefetch_lines};
use super::{Closest, LEAF_ALIGN, PADDING, TraversalStats};
use crate::geometry::triangle::{
    TriangleHit, WatertightRay, finish_decided_hit, intersect_triangle,
};
use crate::geometry::{Geometry, Precision, PrimHit, Primitive};
use crate::math::{Ray, Vec3};
use classify::GroupTest;
pub(crate) use contacts::PackedContacts;

/// Lanes per group: the wide hierarchy aligns its leaves to this.
const LANES: usize = LEAF_ALIGN;

/// Four triangles: `v[3 * k + axis][lane]` is coordinate `axis` of vertex `k`. Lanes that hold
/// no triangle (a sphere, or padding) are NaN, which the filter never rejects. Aligned to 32
/// bytes so each group's 160 bytes lie in three cache lines, which the walk prefetches.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Group {
    v: [[f32; LANES]; 9],
    /// The primitive of each lane, so a candidate needs no look-up in `prim_order`.
    prim: [u32; LANES],
}

/// The corners of lane `lane`. Written out: `[0, 1, 2].map(..)` went through a call to
/// `array::try_map` that was not inlined (33 instructions per ray, callgrind).
#[inline(always)]
fn group_corners(v: &[[f32; LANES]; 9], lane: usize) -> [Vec3; 3] {
    let corner = |k: usize| Vec3::new(v[3 * k][lane], v[3 * k + 1][lane], v[3 * k + 2][lane]);
    [corner(0), corner(1), corner(2)]
}

/// A scene's triangles in the order of one hierarchy's `prim_order`.
#[derive(Clone, Debug)]
pub struct PackedLeaves {
    groups: Vec<Group>,
}

impl PackedLeaves {
    /// Packs the triangles of `geometry` in the order `prim_order` (whose leaves start at
    /// multiples of [`LEAF_ALIGN`] and whose length is one too).
    pub fn new(geometry: &Geometry, prim_order: &[u32]) -> Self {
        let mut groups = crate::huge_pages::vec_with_capacity(prim_order.len().div_ceil(LANES));
        groups.extend(prim_order.chunks(LANES).map(|chunk| {
            let mut g = Group {
                v: [[f32::NAN; LANES]; 9],
                prim: [PADDING; LANES],
            };
            for (lane, &p) in chunk.iter().enumerate() {
                g.prim[lane] = p;
                if p == PADDING {
                    continue;
                }
                if let Primitive::Triangle { mesh, tri } = geometry.prims()[p as usize] {
                    let corners = geometry.meshes()[mesh as usize].corners(tri);
                    for (k, c) in corners.iter().enumerate() {
                        for axis in 0..3 {
                            g.v[3 * k + axis][lane] = c[axis];
                        }
                    }
                }
            }
            g
        }));
        Self { groups }
    }

    /// The corners of the triangle at `slot` (its position in the leaf order), if one is there.
    pub(crate) fn corners(&self, slot: u32) -> Option<[Vec3; 3]> {
        let (g, lane) = (slot as usize / LANES, slot as usize % LANES);
        let v = &self.groups.get(g)?.v;
        if v[0][lane].is_nan() {
            return None;
        }
        Some(group_corners(v, lane))
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        std::mem::size_of_val(self.groups.as_slice())
    }
}

/// The watertight test over packed leaves, for one ray.
pub(crate) struct PackedWatertight<'a> {
    packed: &'a PackedLeaves,
    geometry: &'a Geometry,
    /// The shear and the group test's constants, from the first leaf on.
    shear: Option<(WatertightRay, GroupTest)>,
    /// Where in the leaf order the best hit so far lies ([`NO_SLOT`] before one).
    best_slot: u32,
    /// For an any-hit query: a lane that is not a triangle (an instance) is asked whether it
    /// blocks, not for its nearest hit.
    any_hit: bool,
    /// For a walk that enters instances itself (`wide::inside`): a leaf's instances are not
    /// tested but left in [`Self::deferred`] for the walk to enter.
    enters_instances: bool,
    /// The slots of the last leaf tested that may still hold instances to enter.
    deferred: std::ops::Range<u32>,
}

/// [`PackedWatertight::best_slot`] of a query without a hit.
pub(crate) const NO_SLOT: u32 = u32::MAX;

impl<'a> PackedWatertight<'a> {
    /// The test over `packed`, built from `geometry` (which holds the spheres).
    #[inline(always)]
    pub(crate) fn new(packed: &'a PackedLeaves, geometry: &'a Geometry) -> Self {
        Self {
            packed,
            geometry,
            shear: None,
            best_slot: NO_SLOT,
            any_hit: false,
            enters_instances: false,
            deferred: 0..0,
        }
    }

    /// [`PackedWatertight::new`] for a walk that enters the instances of its leaves itself
    /// ([`Self::next_instance`]).
    #[inline(always)]
    pub(crate) fn entering_instances(packed: &'a PackedLeaves, geometry: &'a Geometry) -> Self {
        Self {
            enters_instances: true,
            ..Self::new(packed, geometry)
        }
    }

    /// [`PackedWatertight::new`] over the tester of an earlier ray, written in place.
    #[inline(always)]
    pub(crate) fn restart(&mut self, packed: &'a PackedLeaves, geometry: &'a Geometry) {
        self.packed = packed;
        self.geometry = geometry;
        self.shear = None;
        self.best_slot = NO_SLOT;
        self.deferred = 0..0;
    }

    /// Tests instances as nested queries again (a ray the walk that enters them hands to the
    /// one-ray walk).
    #[inline(always)]
    pub(crate) fn test_instances(&mut self) {
        self.enters_instances = false;
    }

    /// The next instance the last leaf test left to be entered: its primitive and instance.
    #[inline(always)]
    pub(crate) fn next_instance(&mut self) -> Option<(u32, u32)> {
        for slot in self.deferred.by_ref() {
            let prim = self.packed.groups[slot as usize / LANES].prim[slot as usize % LANES];
            if prim == PADDING {
                continue;
            }
            if let Some(instance) = self.geometry.instance_of(prim) {
                return Some((prim, instance));
            }
        }
        None
    }

    /// Records that the walk took a hit found outside the leaf tests (inside an instance)
    /// as its best: `slot` in the instance's prototype's packed leaves, if there.
    #[inline(always)]
    pub(crate) fn took_entered(&mut self, slot: Option<u32>) {
        self.best_slot = slot.unwrap_or(NO_SLOT);
    }

    /// Whether `prim` is an instance this walk enters itself: then it is not tested but left
    /// for [`Self::next_instance`] ([`defer`]).
    #[inline(always)]
    fn enters(&self, prim: u32) -> bool {
        self.enters_instances && self.geometry.instance_of(prim).is_some()
    }

    /// [`PackedWatertight::new`] for an any-hit query.
    #[inline(always)]
    pub(crate) fn for_any(packed: &'a PackedLeaves, geometry: &'a Geometry) -> Self {
        Self {
            any_hit: true,
            ..Self::new(packed, geometry)
        }
    }

    /// Where in the leaf order the best hit so far lies, if it is a triangle.
    #[inline(always)]
    pub(crate) fn best_slot(&self) -> Option<u32> {
        (self.best_slot != NO_SLOT).then_some(self.best_slot)
    }

    /// Calls `f(prim, slot, hit)` for every hit in the leaf at `first` with `count` entries
    /// (`slot`: the lane's place in the leaf order, [`NO_SLOT`] for a sphere), tested against
    /// `ray` with the `t_max` of the ray `f` returns, until `f` returns `None`.
    #[inline(always)]
    fn each_hit(
        &mut self,
        first: u32,
        count: usize,
        ray: &Ray,
        mut f: impl FnMut(u32, u32, PrimHit) -> Option<Ray>,
    ) {
        if !self.has_triangles(first, count) {
            return self.each_alone_hit(first, count, ray, f);
        }
        if self.shear.is_none() {
            let wr = WatertightRay::new(ray.dir);
            self.shear = Some((wr, GroupTest::new(ray, &wr)));
        }
        // Borrowed, not copied: a copy per leaf cost ~25 instructions per ray (callgrind).
        let Some((wr, test)) = &self.shear else {
            return;
        };
        let mut ray = *ray;
        let mut left = count;
        let mut g = first as usize / LANES;
        while left > 0 {
            let lanes = left.min(LANES);
            let group = &self.packed.groups[g];
            let decided = test.decide_in_range(group, (1 << lanes) - 1, &ray);
            let mut mask = decided.line_hits | decided.scalar;
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let prim = group.prim[lane];
                let v = &group.v;
                let p = group_corners(v, lane);
                let decided_hit = if decided.line_hits & (1 << lane) != 0 {
                    finish_decided_hit(&ray, p, decided.u[lane], decided.v[lane]).ok()
                } else {
                    None
                };
                let slot = (g * LANES + lane) as u32;
                let hit = match decided_hit {
                    Some(h) => h.and_then(|h| self.alpha(prim, h)),
                    // An instance the walk enters itself: left for it, not tested.
                    None if v[0][lane].is_nan() && self.enters(prim) => {
                        defer(&mut self.deferred, slot, first + count as u32);
                        None
                    }
                    // Not a triangle: the geometry's own test (a sphere, an instance); an
                    // any-hit query needs only the verdict, which `f` takes from any hit.
                    None if v[0][lane].is_nan() && self.any_hit => self
                        .geometry
                        .blocks(Precision::Watertight, prim, &ray, wr)
                        .then_some(PrimHit {
                            t: ray.t_max,
                            u: 0.0,
                            v: 0.0,
                            inner: 0,
                        }),
                    None if v[0][lane].is_nan() => self.geometry.intersect(prim, &ray, wr),
                    None => intersect_triangle(&ray, wr, p[0], p[1], p[2])
                        .and_then(|h| self.alpha(prim, h)),
                };
                if let Some(h) = hit {
                    // A slot only for triangles: a hit with one is a triangle whose corners
                    // `corners` reads.
                    let slot = if v[0][lane].is_nan() { NO_SLOT } else { slot };
                    match f(prim, slot, h) {
                        Some(next) => ray = next,
                        None => return,
                    }
                }
            }
            left -= lanes;
            g += 1;
        }
    }

    /// Whether the leaf at `first` with `count` entries holds a triangle (the first lane
    /// usually answers).
    #[inline(always)]
    fn has_triangles(&self, first: u32, count: usize) -> bool {
        (first as usize..first as usize + count)
            .any(|slot| !self.packed.groups[slot / LANES].v[0][slot % LANES].is_nan())
    }

    /// [`PackedWatertight::each_hit`] of a leaf of spheres and instances only (a top level
    /// over instances): each through the geometry's own test, without the shear and the
    /// group test, which only triangles use.
    #[inline(never)]
    fn each_alone_hit(
        &mut self,
        first: u32,
        count: usize,
        ray: &Ray,
        mut f: impl FnMut(u32, u32, PrimHit) -> Option<Ray>,
    ) {
        let mut ray = *ray;
        for slot in first as usize..first as usize + count {
            let prim = self.packed.groups[slot / LANES].prim[slot % LANES];
            if prim == PADDING {
                continue;
            }
            if self.enters(prim) {
                defer(&mut self.deferred, slot as u32, first + count as u32);
                continue;
            }
            let hit = if self.any_hit {
                self.geometry.blocks_alone(prim, &ray).then_some(PrimHit {
                    t: ray.t_max,
                    u: 0.0,
                    v: 0.0,
                    inner: 0,
                })
            } else {
                self.geometry.intersect_alone(prim, &ray)
            };
            if let Some(h) = hit {
                match f(prim, NO_SLOT, h) {
                    Some(next) => ray = next,
                    None => return,
                }
            }
        }
    }

    /// A triangle that passes the exact test must pass its mesh's alpha test too, as in
    /// `Geometry::intersect`.
    #[inline(always)]
    fn alpha(&self, prim: u32, h: TriangleHit) -> Option<PrimHit> {
        // Written out, not `Option::filter`: across the crate split rustc stopped inlining that
        // generic call here (+88 M instructions on tumbledStones, callgrind).
        if self.geometry.alpha_passes(prim, h.u, h.v) {
            Some(h.into())
        } else {
            None
        }
    }
}

/// Leaves the instance at `slot` (and whatever else of its leaf lies before `end`) to
/// [`PackedWatertight::next_instance`]; a leaf's first such slot starts the range.
#[inline(always)]
fn defer(deferred: &mut std::ops::Range<u32>, slot: u32, end: u32) {
    if deferred.start >= deferred.end {
        *deferred = slot..end;
    }
}

impl Prefetch for PackedWatertight<'_> {
    #[inline(always)]
    fn prefetch(&self, first: u32, count: u32) {
        let g = first as usize / LANES;
        for group in self
            .packed
            .groups
            .iter()
            .skip(g)
            .take((count as usize).div_ceil(LANES))
        {
            prefetch_lines(group);
        }
    }
}

impl ClosestLeaves for PackedWatertight<'_> {
    #[inline(always)]
    fn closest(
        &mut self,
        first: u32,
        prims: &[u32],
        closest: &mut Closest,
        stats: &mut TraversalStats,
    ) {
        stats.prim_tests += prims.len() as u64;
        let ray = closest.ray;
        let mut best_slot = self.best_slot;
        self.each_hit(first, prims.len(), &ray, |prim, slot, h| {
            if closest.offer(prim, h) {
                best_slot = slot;
            }
            Some(closest.ray)
        });
        self.best_slot = best_slot;
    }
}

impl AnyLeaves for PackedWatertight<'_> {
    #[inline(always)]
    fn any(&mut self, first: u32, prims: &[u32], ray: &Ray, stats: &mut TraversalStats) -> bool {
        stats.prim_tests += prims.len() as u64;
        let mut blocked = false;
        self.each_hit(first, prims.len(), ray, |_, _, _| {
            blocked = true;
            None
        });
        blocked
    }
}
