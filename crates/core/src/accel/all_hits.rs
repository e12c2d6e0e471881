//! The all-hits query: every surface crossing along a ray, each counted once, and the grazes
//! (touches that do not cross), sorted by `t`. What trimesh's `multiple_hits` and Embree users'
//! re-queries get wrong at shared edges and vertices, where an inclusive test reports a
//! crossing once per triangle touched and an exclusive one may report none.
//!
//! ## The rule
//!
//! A crossing through an edge or a vertex of a closed mesh counts once; a touch that does not
//! cross (a silhouette edge or vertex, a ray lying in a face, a tangent sphere) is reported
//! once, flagged as a graze. Exactly: the ray is symbolically displaced by `(eps, eps^2)` in
//! the watertight test's sheared plane; each triangle touched on its boundary *claims* the
//! ray when the displaced ray crosses it, decided from exact signs
//! ([`crate::geometry::Contact`], whose module states the formulas), and the touches of one
//! mesh at one edge or vertex form one hit: a crossing when an odd number of them claims the
//! ray, else a graze. The displaced ray crosses every closed surface generically, so the
//! crossings reported between two points of the ray have the parity of "one inside, the other
//! outside", for every ray, through any edge or vertex. Interior triangle hits and a sphere's
//! two distinct roots are crossings.
//!
//! Each reported hit's `t` is the smallest any member of its group reports (they meet at one
//! point; each rounds its own plane distance once); its primitive, barycentrics and normal are
//! those of the claiming member with the smallest `(t, index)`, or for a graze of the member
//! with the smallest `(t, index)`. The list is sorted by `t`, ties by primitive index, so the
//! first entry has the nearest-hit query's `t` (the same tests decide what is touched).
//!
//! Every primitive in every leaf whose box the ray's interval enters is tested (the any-hit
//! walk that never stops), once each, on the caller's ray as given, also from far away: the
//! answer is exact for the caller's own line (the nearest-hit query moves a far origin near
//! the scene, which displaces the line by up to half an ulp of the scene's coordinates, see
//! [`super::RayFrame`]). All accelerators and traversals give brute force's answer bit for bit.

use super::Framing;
use super::wide::LevelQueue;
use super::{Accel, NO_SLOT, PackedContacts, TraversalStats};
use crate::geometry::{Contact, Geometry, Precision, PrimHit, Seam, Touch, WatertightRay};
use crate::math::Ray;

/// One hit of the all-hits query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AllHit {
    /// The primitive index.
    pub prim: u32,
    /// Distance and barycentrics (0 for spheres).
    pub hit: PrimHit,
    /// The distance on the caller's ray (the same as `hit.t`: the caller's ray is traced).
    pub t: f32,
    /// A touch that does not cross the surface (see the module docs).
    pub graze: bool,
    /// Where the hit triangle lies in the packed leaves, when it was found there
    /// ([`Accel::packed_corners`] reads its corners, as for [`super::Traced::slot`]); `None`
    /// otherwise. Which accelerator found the hit decides it, nothing else does.
    pub slot: Option<u32>,
}

/// The answer of an all-hits query.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AllHits {
    /// The ray traced, the caller's; `None` when it misses the scene's bounds. Surfaces of
    /// [`AllHits::hits`] are computed on it.
    pub ray: Option<Ray>,
    /// Every hit in the caller's `(t_min, t_max]`, sorted by `t`, ties by primitive index.
    pub hits: Vec<AllHit>,
}

/// Buffers an all-hits query reuses from one ray to the next (a batch keeps one per thread),
/// so a ray costs no allocation once they have grown.
#[derive(Clone, Debug, Default)]
pub struct AllHitsScratch {
    prims: Vec<u32>,
    contacts: Vec<Contact>,
    /// The packed-leaf slot of each contact ([`AllHit::slot`], [`NO_SLOT`] for none).
    slots: Vec<u32>,
    seams: Vec<(Seam, bool, Contact, u32)>,
    queue: LevelQueue,
}

impl Accel {
    /// Every surface crossing and graze of `ray` among the primitives of `geometry` (the
    /// geometry this was built for), by the rule of the module docs. `precision` chooses the
    /// triangle and sphere tests as for the nearest hit, except that `Fast` (whose edge
    /// decisions are not exact, so no rule could count with it) uses the watertight tests.
    pub fn all_hits_geometry(
        &self,
        geometry: &Geometry,
        precision: Precision,
        ray: &Ray,
        stats: &mut TraversalStats,
    ) -> AllHits {
        let mut hits = Vec::new();
        let traced = self.all_hits_into(
            geometry,
            precision,
            ray,
            stats,
            &mut AllHitsScratch::default(),
            &mut hits,
        );
        AllHits { ray: traced, hits }
    }

    /// [`Accel::all_hits_geometry`] into `hits` (cleared first), with buffers from `scratch`:
    /// returns [`AllHits::ray`] and leaves [`AllHits::hits`] in `hits`.
    pub fn all_hits_into(
        &self,
        geometry: &Geometry,
        precision: Precision,
        ray: &Ray,
        stats: &mut TraversalStats,
        scratch: &mut AllHitsScratch,
        hits: &mut Vec<AllHit>,
    ) -> Option<Ray> {
        hits.clear();
        // Exact on the caller's own line: a far origin is not moved near the scene, as the
        // nearest-hit query moves it, since the rounding of the moved origin displaces the line
        // by up to half an ulp of the scene's coordinates, and a ray that only touches an edge
        // or a vertex would then cross two faces instead (or miss). Every decision below is
        // exact for any finite `f32` ray, and the walk's box tests are conservative at any
        // distance; the frame only answers whether the line meets the scene at all.
        if matches!(self.frame.frame(ray), Framing::Miss) {
            return None;
        }
        let (contacts, slots) = (&mut scratch.contacts, &mut scratch.slots);
        contacts.clear();
        slots.clear();
        match self.packed() {
            // The packed leaves hold each primitive once and test the watertight way.
            Some((wide, packed)) if precision != Precision::Double => {
                let mut test = PackedContacts::new(packed, geometry, precision, contacts, slots);
                wide.each_leaf(ray, stats, &mut test, &mut scratch.queue);
            }
            _ => {
                // Every primitive of every leaf the interval enters, in whatever order the
                // walk takes, once each (a partition may list one in several leaves).
                let prims = &mut scratch.prims;
                prims.clear();
                self.any(ray, stats, |p, _| {
                    prims.push(p);
                    false
                });
                prims.sort_unstable();
                prims.dedup();
                let wr = WatertightRay::new(ray.dir);
                for &p in prims.iter() {
                    geometry.contacts(p, ray, &wr, precision, contacts);
                }
                slots.resize(contacts.len(), NO_SLOT);
            }
        }
        resolve(contacts, slots, &mut scratch.seams, hits);
        // Stable: a sphere's two roots rounded to one `t` keep their order. The contacts of
        // one primitive are consecutive and in its own order whatever the walk's order, and
        // only those can tie on `(t, prim)`: the list does not depend on the walk.
        hits.sort_by(|a, b| by_t(a.t, b.t).then(a.prim.cmp(&b.prim)));
        Some(*ray)
    }
}

/// Pushes onto `out` the hits of `contacts` (found at `slots`): crossings and grazes as they
/// are, and one hit per seam (see the module docs), with its graze flag; crossings and grazes
/// first, then the seams in seam order. `seams` is scratch space. A distance beyond
/// `f32::MAX` is no `f32` distance: no hit, as for the other queries.
fn resolve(
    contacts: &[Contact],
    slots: &[u32],
    seams: &mut Vec<(Seam, bool, Contact, u32)>,
    out: &mut Vec<AllHit>,
) {
    let mut push = |c: Contact, slot: u32, graze: bool| {
        if c.hit.t.is_finite() {
            out.push(AllHit {
                prim: c.prim,
                hit: c.hit,
                t: c.hit.t,
                graze,
                slot: (slot != NO_SLOT).then_some(slot),
            });
        }
    };
    seams.clear();
    for (&c, &slot) in contacts.iter().zip(slots) {
        match c.touch {
            Touch::Crossing => push(c, slot, false),
            Touch::Graze => push(c, slot, true),
            Touch::Boundary { seam, claims } => seams.push((seam, claims, c, slot)),
        }
    }
    if seams.is_empty() {
        return;
    }
    let order = |a: &Contact, b: &Contact| by_t(a.hit.t, b.hit.t).then(a.prim.cmp(&b.prim));
    seams.sort_by(|a, b| a.0.cmp(&b.0).then(order(&a.2, &b.2)));
    for group in seams.chunk_by(|a, b| a.0 == b.0) {
        let claimers = group.iter().filter(|m| m.1).count();
        let crossing = claimers % 2 == 1;
        // Sorted by (t, index): the first member has the group's t.
        let t = group[0].2.hit.t;
        let (_, _, mut rep, slot) = if crossing {
            *group.iter().find(|m| m.1).unwrap_or(&group[0])
        } else {
            group[0]
        };
        rep.hit.t = t;
        push(rep, slot, !crossing);
    }
}

/// Distances in IEEE order, as the nearest-hit query compares them: `-0 == +0` (a tie, broken
/// by primitive index). Never NaN.
fn by_t(a: f32, b: f32) -> std::cmp::Ordering {
    a.partial_cmp(&b).unwrap_or(std::cmp::Ordering::Equal)
}

#[cfg(test)]
mod tests;
