//! Several closest-hit walks in flight on one thread, for batches of independent rays: each
//! ray advances up to its next node visit (which starts loading the children it entered) and
//! then the next ray takes its turn, so the loads one ray waits for overlap the other rays'
//! work instead of stalling the thread. A finished ray's lane takes the next ray of the batch.
//!
//! Each ray takes the steps of its one-ray walk ([`NearestWalk`]) in the same order, only
//! interleaved with other rays', so every answer is the one-ray walk's, bit for bit. Over a
//! top level of instances, a ray enters each instance its leaf tests meet as more steps of its
//! own ([`super::inside`]), with the answer the one-ray walk's nested query gives.

use super::child_test::{ChildTest, Octant};
use super::inside::{Entered, Inside, walking};
use super::nearest::{NearestStack, NearestWalk};
use super::{SimdPath, WideBvh};
use crate::accel::leaves::ClosestLeaves;
use crate::accel::{Hit, TraversalStats};
use crate::math::Ray;

/// Where the rays of a batch walk come from and where their answers go.
pub(crate) trait NearestQueries<'a> {
    /// What names a ray to its answer.
    type Id: Copy;
    /// The leaf tester a ray is walked with.
    type Leaves: ClosestLeaves;
    /// Whether the leaf tests leave instances for the walk to enter ([`Self::enter`]).
    const ENTERS_INSTANCES: bool;

    /// The next ray to walk and its tester; `None` once every ray has been handed out.
    fn next(&mut self, stats: &mut TraversalStats) -> Option<(Self::Id, Ray, Self::Leaves)>;

    /// The nearest hit of ray `id` (`ray` as [`Self::next`] gave it), and its tester as the
    /// walk left it.
    fn answer(&mut self, id: Self::Id, ray: &Ray, hit: Option<Hit>, leaves: &Self::Leaves);

    /// The next instance the last leaf test of `leaves` left to be entered, entered from
    /// `ray` (the walk's ray as it has shrunk), its walk started on `stack` and written into
    /// `inside`; `None` when none is left.
    fn enter(
        &self,
        leaves: &mut Self::Leaves,
        ray: &Ray,
        stack: &mut NearestStack,
        inside: &mut Option<Inside<'a>>,
    ) -> Option<Entered>;

    /// The answer of a finished walk inside an instance: the instance's primitive, its hit on
    /// the caller's ray and the hit triangle's slot in the prototype's packed leaves.
    fn leave(&self, inside: &Inside<'a>) -> Option<(u32, crate::geometry::PrimHit, Option<u32>)>;

    /// Records that the walk's best hit is now one found inside an instance.
    fn took_entered(leaves: &mut Self::Leaves, slot: Option<u32>);

    /// Makes `leaves` test instances themselves, as nested queries: for a ray walked whole
    /// by the one-ray walk, which enters none.
    fn alone(leaves: &mut Self::Leaves);
}

impl WideBvh<8> {
    /// Answers every ray of `queries` with up to `K` walks in flight (`K = 1`: one ray at a
    /// time). Without AVX2 the rays are walked one at a time.
    pub(crate) fn intersect_in_flight<'a, const K: usize, Q: NearestQueries<'a>>(
        &self,
        queries: &mut Q,
        stats: &mut TraversalStats,
    ) {
        match SimdPath::active() {
            // SAFETY: the CPU has what each path needs (`SimdPath::active`).
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx512 if K > 1 => unsafe { self.in_flight_avx512::<K, Q>(queries, stats) },
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx2 if K > 1 => unsafe { self.in_flight_avx2::<K, Q>(queries, stats) },
            _ => {
                while let Some((id, ray, mut leaves)) = queries.next(stats) {
                    Q::alone(&mut leaves);
                    let hit = self.intersect(&ray, stats, &mut leaves);
                    queries.answer(id, &ray, hit, &leaves);
                }
            }
        }
    }

    /// The interleaved walks, compiled for AVX2 like the one-ray walk.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
    unsafe fn in_flight_avx2<'a, const K: usize, Q: NearestQueries<'a>>(
        &self,
        queries: &mut Q,
        stats: &mut TraversalStats,
    ) {
        self.in_flight_simd::<K, Q, _, _>(super::child_test::Avx2, queries, stats)
    }

    /// The interleaved walks, compiled for AVX-512 like the one-ray walk.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl")]
    unsafe fn in_flight_avx512<'a, const K: usize, Q: NearestQueries<'a>>(
        &self,
        queries: &mut Q,
        stats: &mut TraversalStats,
    ) {
        self.in_flight_simd::<K, Q, _, _>(super::avx512::Avx512, queries, stats)
    }

    /// The interleaved walks with the SIMD child test `simd` makes.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn in_flight_simd<
        'a,
        const K: usize,
        Q: NearestQueries<'a>,
        T: ChildTest<8>,
        F: Fn(Octant) -> T + Copy,
    >(
        &self,
        simd: F,
        queries: &mut Q,
        stats: &mut TraversalStats,
    ) {
        // Lane by lane: an array constant was copied whole, unused stack space included.
        let mut lanes: [Lane<'a, Q, T>; K] = std::array::from_fn(|_| Lane {
            stack: NearestStack::new(),
            ray: None,
        });
        let mut live = 0;
        for lane in &mut lanes {
            live += self.start_next(simd, queries, lane, stats) as usize;
        }
        if Q::ENTERS_INSTANCES {
            return self.two_level_in_flight(simd, &mut lanes, live, queries, stats);
        }
        while live > 0 {
            for lane in &mut lanes {
                let Some(r) = &mut lane.ray else { continue };
                // Up to and including the next node visit, which starts the loads this ray
                // waits for next; the entries a leaf test pops were prefetched at their
                // parent's visit (switching after leaf tests too measured 2-3% slower).
                let mut going = true;
                let mut visited_node = false;
                while going && !visited_node {
                    visited_node = r.walk.at_node();
                    going = r.walk.step(self, &mut lane.stack, &mut r.leaves, stats);
                }
                if going {
                    continue;
                }
                queries.answer(r.id, &r.ray, r.walk.best(), &r.leaves);
                live -= !self.start_next(simd, queries, lane, stats) as usize;
            }
        }
    }

    /// The interleaved walks over a top level of instances: as the one-level loop, each ray
    /// stepping into the instances its leaves leave (kept apart so the loop without
    /// instances is unchanged).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn two_level_in_flight<
        'a,
        const K: usize,
        Q: NearestQueries<'a>,
        T: ChildTest<8>,
        F: Fn(Octant) -> T + Copy,
    >(
        &self,
        simd: F,
        lanes: &mut [Lane<'a, Q, T>; K],
        mut live: usize,
        queries: &mut Q,
        stats: &mut TraversalStats,
    ) {
        // Each lane's walk inside an instance, apart from the lanes (whose stacks stay as
        // close together as without instances).
        let mut insides: [InsideSlot<'a>; K] = std::array::from_fn(|_| InsideSlot::default());
        while live > 0 {
            for (lane, inside) in lanes.iter_mut().zip(&mut insides) {
                let Some(r) = &mut lane.ray else { continue };
                if r.advance_two_level(self, &mut lane.stack, inside, queries, stats) {
                    continue;
                }
                queries.answer(r.id, &r.ray, r.walk.best(), &r.leaves);
                inside.top_done = false;
                live -= !self.start_next(simd, queries, lane, stats) as usize;
            }
        }
    }

    /// The walk of the next ray that takes the SIMD child test, started on `stack`. Rays
    /// that need another test (a zero or extreme direction component) are rare: they are
    /// walked whole, one at a time, on the way.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn start_next<'a, Q: NearestQueries<'a>, T: ChildTest<8>, F: Fn(Octant) -> T + Copy>(
        &self,
        simd: F,
        queries: &mut Q,
        lane: &mut Lane<'a, Q, T>,
        stats: &mut TraversalStats,
    ) -> bool {
        use crate::math::safe_inverse;
        use crate::math::slab::SlabKind;
        loop {
            let Some((id, ray, leaves)) = queries.next(stats) else {
                lane.ray = None;
                return false;
            };
            // As the one-ray walk chooses, so the walk is the one-ray walk's.
            let inv = safe_inverse(ray.dir);
            if let SlabKind::Finite = SlabKind::with_inverse(&ray, inv) {
                let test = simd(Octant::new(&ray, inv.to_array()));
                match NearestWalk::start(self, test, &ray, &mut lane.stack) {
                    Some(walk) => {
                        // Written in place: a ray in flight is 400 bytes.
                        lane.ray = Some(InFlight {
                            id,
                            ray,
                            leaves,
                            walk,
                        });
                        return true;
                    }
                    None => queries.answer(id, &ray, None, &leaves),
                }
                continue;
            }
            self.intersect_one(queries, id, &ray, leaves, stats);
        }
    }

    /// One ray walked whole: kept out of line so the rare rays that need it do not bloat
    /// the batch walk's loop.
    #[cold]
    #[inline(never)]
    fn intersect_one<'a, Q: NearestQueries<'a>>(
        &self,
        queries: &mut Q,
        id: Q::Id,
        ray: &Ray,
        mut leaves: Q::Leaves,
        stats: &mut TraversalStats,
    ) {
        Q::alone(&mut leaves);
        let hit = self.intersect(ray, stats, &mut leaves);
        queries.answer(id, ray, hit, &leaves);
    }
}

/// One of the batch walk's places for a ray: the stack, which stays put (5 KB), and the ray
/// in flight there, if any.
#[cfg(target_arch = "x86_64")]
struct Lane<'a, Q: NearestQueries<'a>, T> {
    stack: NearestStack,
    ray: Option<InFlight<'a, Q, T>>,
}

/// A lane's walk inside the instance its ray is in, if any, with its own stack (kept apart
/// from the ray's [`InFlight`], so that starting a ray does not copy its 400 bytes).
#[cfg(target_arch = "x86_64")]
struct InsideSlot<'a> {
    stack: NearestStack,
    walk: Option<Inside<'a>>,
    /// The ray's top-level walk is done (instances its last leaf left may still be entered).
    top_done: bool,
}

#[cfg(target_arch = "x86_64")]
impl Default for InsideSlot<'_> {
    fn default() -> Self {
        Self {
            stack: NearestStack::new(),
            walk: None,
            top_done: false,
        }
    }
}

/// A ray in flight: its name, the ray, its tester and its walk.
#[cfg(target_arch = "x86_64")]
struct InFlight<'a, Q: NearestQueries<'a>, T> {
    id: Q::Id,
    ray: Ray,
    leaves: Q::Leaves,
    walk: NearestWalk<T>,
}

#[cfg(target_arch = "x86_64")]
impl<'a, Q: NearestQueries<'a>, T: ChildTest<8>> InFlight<'a, Q, T> {
    /// Steps up to and including the next node visit (of either level), entering the
    /// instances each leaf test leaves, in order; true while the ray has more to visit.
    #[inline(always)]
    fn advance_two_level(
        &mut self,
        bvh: &WideBvh<8>,
        stack: &mut NearestStack,
        inside: &mut InsideSlot<'a>,
        queries: &Q,
        stats: &mut TraversalStats,
    ) -> bool {
        // Most turns: a walk inside under way, stepped as the one-level walk steps.
        if let Some(walk) = walking(&mut inside.walk)
            && self.step_inside(walk, &mut inside.stack, queries, stats)
        {
            return true;
        }
        self.advance_top(bvh, stack, inside, queries, stats)
    }

    /// Steps the walk inside an instance up to and including its next node visit (true), or
    /// to its end, whose answer it offers to the ray's walk (false).
    #[inline(always)]
    fn step_inside(
        &mut self,
        walk: &mut Inside<'a>,
        stack: &mut NearestStack,
        queries: &Q,
        stats: &mut TraversalStats,
    ) -> bool {
        loop {
            let at_node = walk.at_node();
            if !walk.step(stack, stats) {
                break;
            }
            if at_node {
                return true;
            }
        }
        if let Some((prim, hit, slot)) = queries.leave(walk)
            && self.walk.offer(prim, hit)
        {
            Q::took_entered(&mut self.leaves, slot);
        }
        walk.finish();
        false
    }

    /// The other turns: entering the instances the last leaf test left (in order), and the
    /// top level's steps.
    #[inline(always)]
    fn advance_top(
        &mut self,
        bvh: &WideBvh<8>,
        stack: &mut NearestStack,
        inside: &mut InsideSlot<'a>,
        queries: &Q,
        stats: &mut TraversalStats,
    ) -> bool {
        loop {
            loop {
                let ray = self.walk.ray();
                match queries.enter(&mut self.leaves, ray, &mut inside.stack, &mut inside.walk) {
                    None => break,
                    Some(Entered::Walk) => {
                        if let Some(walk) = walking(&mut inside.walk)
                            && self.step_inside(walk, &mut inside.stack, queries, stats)
                        {
                            return true;
                        }
                    }
                    Some(Entered::Answered(prim, hit)) => {
                        if let Some(h) = hit
                            && self.walk.offer(prim, h)
                        {
                            Q::took_entered(&mut self.leaves, None);
                        }
                    }
                }
            }
            if inside.top_done {
                return false;
            }
            let at_node = self.walk.at_node();
            inside.top_done = !self.walk.step(bvh, stack, &mut self.leaves, stats);
            if at_node && !inside.top_done {
                return true;
            }
        }
    }
}
