//! Entering an instance in place: when the batch walk's leaf test meets an instance, the
//! ray's walk continues into the prototype's own hierarchy as more steps of the same lane
//! (its object-space ray, its packed leaves, a stack of its own), interleaved with the other
//! rays in flight like any other step, instead of as a nested query that runs to the end
//! while the thread waits on its loads. Embree and OptiX switch ray and node array at an
//! instance leaf in the same way.
//!
//! A walk inside takes the steps the prototype's own query would take for the same
//! object-space ray ([`crate::geometry::PrototypeQueries::nearest`] through the wide hierarchy
//! and packed leaves), so its answer is that query's, bit for bit; rays that query would trace
//! another way (moved from far away, or needing another child test) are answered by the query
//! itself, at once.

use super::WideBvh;
use super::child_test::{Avx2, Octant};
use super::nearest::{NearestStack, NearestWalk};
use crate::accel::packed::PackedWatertight;
use crate::accel::{Accel, Hit, TraversalStats};
use crate::geometry::{Geometry, PrimHit};
use crate::math::safe_inverse;
use crate::math::slab::SlabKind;

/// A walk inside one instance.
pub(crate) struct Inside<'a> {
    walk: NearestWalk<Avx2>,
    bvh: &'a WideBvh<8>,
    leaves: PackedWatertight<'a>,
    /// The instance's primitive in the walk it was entered from.
    prim: u32,
    /// Under way (a finished walk stays in its slot, to be written over by the next).
    active: bool,
}

/// The walk in `slot`, if one is under way.
#[inline(always)]
pub(super) fn walking<'s, 'a>(slot: &'s mut Option<Inside<'a>>) -> Option<&'s mut Inside<'a>> {
    slot.as_mut().filter(|w| w.active)
}

/// What entering an instance gives: a walk to step (written where the caller asked), or the
/// answer at once.
pub(crate) enum Entered {
    Walk,
    /// The instance's primitive and its hit, if any.
    Answered(u32, Option<PrimHit>),
}

/// Enters instance `instance` (primitive `prim` of `geometry`) from `ray`, the walk's ray as
/// it has shrunk so far: its walk into `inside` (built there, not moved: it is 400 bytes),
/// started on `stack`.
#[inline(always)]
pub(crate) fn enter<'a>(
    geometry: &'a Geometry,
    prim: u32,
    instance: u32,
    ray: &crate::math::Ray,
    stack: &mut NearestStack,
    inside: &mut Option<Inside<'a>>,
) -> Entered {
    // A ray from far away is framed for the instance first: the nested query does that.
    let (prototype, object) = match geometry.instance_ray_as_given(instance, ray) {
        Ok(Some(entered)) => entered,
        Ok(None) => return Entered::Answered(prim, None),
        Err(()) => return Entered::Answered(prim, geometry.intersect_alone(prim, ray)),
    };
    let proto = &geometry.prototypes()[prototype as usize];
    let walkable = proto
        .hierarchy()
        .downcast_ref::<Accel>()
        .filter(|a| a.frame().holds(object.origin))
        .and_then(Accel::packed);
    let inv = safe_inverse(object.dir);
    match walkable {
        Some((bvh, packed)) if SlabKind::with_inverse(&object, inv) == SlabKind::Finite => {
            let test = Avx2(Octant::new(&object, inv.to_array()));
            match NearestWalk::start(bvh, test, &object, stack) {
                Some(walk) => {
                    // Field by field over the last walk: a whole new value was built on the
                    // stack and copied (the copy's loads stalled on the stores before them).
                    match inside {
                        Some(w) => {
                            w.walk = walk;
                            w.bvh = bvh;
                            w.leaves.restart(packed, proto.geometry());
                            w.prim = prim;
                            w.active = true;
                        }
                        None => {
                            *inside = Some(Inside {
                                walk,
                                bvh,
                                leaves: PackedWatertight::new(packed, proto.geometry()),
                                prim,
                                active: true,
                            })
                        }
                    }
                    Entered::Walk
                }
                None => Entered::Answered(prim, None),
            }
        }
        // As the nested query answers it.
        _ => Entered::Answered(prim, geometry.intersect_alone(prim, ray)),
    }
}

impl Inside<'_> {
    /// Whether the next step visits a node.
    #[inline(always)]
    pub(super) fn at_node(&self) -> bool {
        self.walk.at_node()
    }

    /// One step of the walk inside (see [`NearestWalk::step`]); false once it is done.
    #[inline(always)]
    pub(super) fn step(&mut self, stack: &mut NearestStack, stats: &mut TraversalStats) -> bool {
        self.walk.step(self.bvh, stack, &mut self.leaves, stats)
    }

    /// Marks the walk finished.
    #[inline(always)]
    pub(super) fn finish(&mut self) {
        self.active = false;
    }

    /// The finished walk's answer as a hit of the instance's primitive (its `t` on the
    /// object-space ray is the caller's: the ray was traced as given), with the hit
    /// triangle's slot in the prototype's packed leaves.
    #[inline(always)]
    pub(crate) fn answer(&self) -> Option<(u32, PrimHit, Option<u32>)> {
        let Hit { prim: inner, hit } = self.walk.best()?;
        // As the prototype's query reports it: its primitive in `inner`.
        Some((self.prim, PrimHit { inner, ..hit }, self.leaves.best_slot()))
    }
}
