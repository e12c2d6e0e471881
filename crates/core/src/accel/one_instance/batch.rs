//! Batch queries ([`Accel::trace_geometry_each`]) of a scene of one instance: the world rays
//! enter the instance [`ENTRY_BLOCK`] at a time and their object-space images go straight to
//! the prototype's batch walk (`wide::in_flight`) as its rays, so each ray is set up once: no
//! second pass over it, no ray source in between handing over copies.

use super::OnlyInstance;
use crate::accel::wide::{Entered, Inside, NearestQueries, NearestStack};
use crate::accel::{Accel, Hit, PackedLeaves, PackedWatertight, PrimHit, Traced, TraversalStats};
use crate::geometry::{ENTRY_BLOCK, Entries, Entry, Geometry, Precision};
use crate::math::Ray;

impl Accel {
    /// [`Accel::trace_geometry_each`] of a scene of one instance: rays whose object-space
    /// images the prototype can trace as given go to its batch walk, `K` at a time; the others
    /// are answered on the way as [`Accel::trace_geometry`] answers them.
    #[inline(never)]
    pub(in crate::accel) fn trace_each_in_only_instance<const K: usize, Id: Copy>(
        &self,
        only: OnlyInstance,
        geometry: &Geometry,
        stats: &mut TraversalStats,
        mut rays: impl FnMut() -> Option<(Id, Ray)>,
        mut answer: impl FnMut(Id, Option<Traced>),
    ) {
        let precision = Precision::Watertight;
        let walked = only.prototype(geometry).and_then(|(accel, shapes)| {
            let (wide, packed) = accel.packed()?;
            // Prototypes hold no instances (two levels): their leaves are only tested.
            (!shapes.has_instances()).then_some((wide, accel, shapes, packed))
        });
        let Some((wide, accel, shapes, packed)) = walked else {
            while let Some((id, ray)) = rays() {
                answer(id, self.trace_geometry(geometry, precision, &ray, stats));
            }
            return;
        };
        // The first ray the scene's frame holds starts the first block (and fills its ids:
        // no id type has a default).
        let Some(first) = self.next_held(geometry, &mut rays, &mut answer, stats) else {
            return;
        };
        let mut queries = InstanceQueries {
            top: self,
            geometry,
            only,
            prototype: accel,
            shapes,
            packed,
            rays,
            answer,
            block: EntryBlock::new(first),
        };
        wide.intersect_in_flight::<K, _>(&mut queries, stats);
    }

    /// The next ray of `rays` this accelerator's frame holds; those it does not are answered
    /// on the way (the scene's query moves them near the scene first).
    #[inline(always)]
    fn next_held<Id>(
        &self,
        geometry: &Geometry,
        rays: &mut impl FnMut() -> Option<(Id, Ray)>,
        answer: &mut impl FnMut(Id, Option<Traced>),
        stats: &mut TraversalStats,
    ) -> Option<(Id, Ray)> {
        loop {
            let (id, ray) = rays()?;
            if self.frame.holds(ray.origin) {
                return Some((id, ray));
            }
            answer(
                id,
                self.trace_geometry(geometry, Precision::Watertight, &ray, stats),
            );
        }
    }
}

/// The rays of a batch through a scene of one instance, as the prototype's batch walk asks for
/// them: world rays from `rays`, entered into the instance a block at a time; the walk's rays
/// are their object-space images and its ids carry the world rays, whose hits `answer` gets.
struct InstanceQueries<'a, Id, R, A> {
    /// The scene's accelerator and shapes (rays it frames first are answered by their query).
    top: &'a Accel,
    geometry: &'a Geometry,
    only: OnlyInstance,
    /// The prototype's accelerator, shapes and packed leaves.
    prototype: &'a Accel,
    shapes: &'a Geometry,
    packed: &'a PackedLeaves,
    rays: R,
    answer: A,
    block: EntryBlock<Id>,
}

impl<Id: Copy, R, A> InstanceQueries<'_, Id, R, A>
where
    R: FnMut() -> Option<(Id, Ray)>,
    A: FnMut(Id, Option<Traced>),
{
    /// Fills the block with the next rays the scene's frame holds and enters them; the rays
    /// the prototype's batch walk takes are left in `block.walked`, the others answered on the
    /// way. `false` once the source has run out. Once per block: out of line, so the walk's
    /// loop keeps only the hand-out.
    #[inline(never)]
    fn refill(&mut self, stats: &mut TraversalStats) -> bool {
        loop {
            let block = &mut self.block;
            let mut n = std::mem::take(&mut block.pending);
            // The source is not asked again once it has run out.
            while n < ENTRY_BLOCK && !block.exhausted {
                let next =
                    self.top
                        .next_held(self.geometry, &mut self.rays, &mut self.answer, stats);
                let Some((id, ray)) = next else {
                    block.exhausted = true;
                    break;
                };
                block.ids[n] = id;
                block.rays[n] = ray;
                n += 1;
            }
            if n == 0 {
                return false;
            }
            let frame = &self.prototype.frame;
            let entries = &mut block.entries;
            self.geometry
                .enter_instance(self.only.instance, &block.rays[..n], frame, entries);
            // As the prototype's own batch query takes its rays.
            let walked = entries.held;
            block.walked = walked;
            let aside = !walked & ((1 << n) - 1);
            if aside != 0 {
                self.answer_aside(aside, stats);
            }
            if walked != 0 {
                return true;
            }
        }
    }

    /// Answers the block's rays in `lanes`, which the prototype's batch walk does not take:
    /// they miss the instance's box, or the instance or the prototype frames them first.
    #[cold]
    #[inline(never)]
    fn answer_aside(&mut self, mut lanes: u32, stats: &mut TraversalStats) {
        let precision = Precision::Watertight;
        while lanes != 0 {
            let k = lanes.trailing_zeros() as usize;
            lanes &= lanes - 1;
            let (id, world) = (self.block.ids[k], self.block.rays[k]);
            let traced = match self.block.entries.entry(k) {
                Entry::Object(object) => self
                    .prototype
                    .trace_far(self.shapes, precision, &object, stats)
                    .map(|f| self.only.traced_on(&world, f)),
                Entry::Misses => None,
                Entry::Framed => self
                    .top
                    .trace_geometry(self.geometry, precision, &world, stats),
            };
            (self.answer)(id, traced);
        }
    }
}

impl<'a, Id, R, A> NearestQueries<'a> for InstanceQueries<'a, Id, R, A>
where
    Id: Copy,
    R: FnMut() -> Option<(Id, Ray)>,
    A: FnMut(Id, Option<Traced>),
{
    type Id = (Id, Ray);
    type Leaves = PackedWatertight<'a>;
    const ENTERS_INSTANCES: bool = false;

    #[inline(always)]
    fn next(&mut self, stats: &mut TraversalStats) -> Option<((Id, Ray), Ray, Self::Leaves)> {
        if self.block.walked == 0 && !self.refill(stats) {
            return None;
        }
        let block = &mut self.block;
        let k = block.walked.trailing_zeros() as usize;
        block.walked &= block.walked - 1;
        let leaves = PackedWatertight::new(self.packed, self.shapes);
        Some((
            (block.ids[k], block.rays[k]),
            block.entries.objects[k],
            leaves,
        ))
    }

    #[inline(always)]
    fn answer(
        &mut self,
        (id, world): (Id, Ray),
        ray: &Ray,
        hit: Option<Hit>,
        leaves: &Self::Leaves,
    ) {
        // As the prototype's batch query answers `ray`, carried back to the world ray.
        let traced = hit.map(|h| {
            let found = Traced::on(ray, (h, leaves.best_slot()), h.hit.t);
            self.only.traced_on(&world, found)
        });
        (self.answer)(id, traced);
    }

    fn enter(
        &self,
        _: &mut Self::Leaves,
        _: &Ray,
        _: &mut NearestStack,
        _: &mut Option<Inside<'a>>,
    ) -> Option<Entered> {
        None
    }

    fn leave(&self, inside: &Inside<'a>) -> Option<(u32, PrimHit, Option<u32>)> {
        inside.answer()
    }

    fn took_entered(_: &mut Self::Leaves, _: Option<u32>) {}

    #[inline(always)]
    fn alone(_: &mut Self::Leaves) {}
}

/// Rays of a batch waiting to be walked, entered into the instance together.
struct EntryBlock<Id> {
    ids: [Id; ENTRY_BLOCK],
    rays: [Ray; ENTRY_BLOCK],
    entries: Entries,
    /// The lanes still to be handed to the walk.
    walked: u32,
    /// Rays held but not yet entered (the first block's first ray).
    pending: usize,
    /// The source has given its last ray.
    exhausted: bool,
}

impl<Id: Copy> EntryBlock<Id> {
    fn new(first: (Id, Ray)) -> Self {
        Self {
            ids: [first.0; ENTRY_BLOCK],
            rays: [first.1; ENTRY_BLOCK],
            entries: Entries::new(),
            walked: 0,
            pending: 1,
            exhausted: false,
        }
    }
}
