//! Batch queries ([`Accel::trace_geometry_each`]) of a scene of one instance: the world rays
//! enter the instance [`ENTRY_BLOCK`] at a time and their object-space images go straight to
//! the prototype's batch walk (`wide::in_flight`) as its rays, so each ray is set up once: no
//! second pass over it, no ray source in between handing over copies.

use super::OnlyInstance;
use crate::accel::wide::{Entered, Inside, NearestQueries, NearestStack};
use crate::accel::{Accel, Hit, PackedLeaves, PackedWatertight, PrimHit, Traced, TraversalStats};
use crate::geometry::{ENTRY_BLOCK, Entries, Entry, Geometry, Precision};
use crate::math::{Ray, Vec3};

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
        let mut queries = InstanceQueries {
            top: self,
            geometry,
            only,
            prototype: accel,
            shapes,
            packed,
            rays,
            answer,
            block: EntryBlock::new(),
        };
        wide.intersect_in_flight::<K, _>(&mut queries, stats);
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
    /// Fills the block with the next rays the scene's frame holds and enters them (the others
    /// are answered on the way); `false` once the source has run out. Once per block: out of
    /// line, so the walk's loop keeps only the hand-out.
    #[inline(never)]
    fn refill(&mut self, stats: &mut TraversalStats) -> bool {
        let block = &mut self.block;
        block.next = 0;
        block.len = 0;
        // The source is not asked again once it has run out.
        while block.len < ENTRY_BLOCK && !block.exhausted {
            let Some((id, ray)) = (self.rays)() else {
                block.exhausted = true;
                break;
            };
            if !self.top.frame.holds(ray.origin) {
                // Moved near the scene first: the top level's query frames it.
                let traced =
                    self.top
                        .trace_geometry(self.geometry, Precision::Watertight, &ray, stats);
                (self.answer)(id, traced);
                continue;
            }
            block.ids[block.len] = Some(id);
            block.rays[block.len] = ray;
            block.len += 1;
        }
        let n = block.len;
        self.geometry
            .enter_instance(self.only.instance, &block.rays[..n], &mut block.entries);
        n > 0
    }

    /// The answer to world ray `world` of the prototype's answer `found` on its image.
    #[cold]
    fn answer_aside(&mut self, id: Id, world: &Ray, found: Option<Traced>) {
        (self.answer)(id, found.map(|f| self.only.traced_on(world, f)));
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
        loop {
            if self.block.next == self.block.len && !self.refill(stats) {
                return None;
            }
            let k = self.block.next;
            self.block.next += 1;
            let (Some(id), world) = (self.block.ids[k], self.block.rays[k]) else {
                unreachable!("rays below `len` have ids")
            };
            match self.block.entries.entry(k) {
                // As the prototype's own batch query takes its rays.
                Entry::Object(object) if self.prototype.frame.holds(object.origin) => {
                    let leaves = PackedWatertight::new(self.packed, self.shapes);
                    return Some(((id, world), object, leaves));
                }
                Entry::Object(object) => {
                    let far = self.prototype.trace_far(
                        self.shapes,
                        Precision::Watertight,
                        &object,
                        stats,
                    );
                    self.answer_aside(id, &world, far);
                }
                Entry::Misses => (self.answer)(id, None),
                Entry::Framed => {
                    let traced = self.top.trace_geometry(
                        self.geometry,
                        Precision::Watertight,
                        &world,
                        stats,
                    );
                    (self.answer)(id, traced);
                }
            }
        }
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
    ids: [Option<Id>; ENTRY_BLOCK],
    rays: [Ray; ENTRY_BLOCK],
    entries: Entries,
    /// Rays held, and the next one to hand out.
    len: usize,
    next: usize,
    /// The source has given its last ray.
    exhausted: bool,
}

impl<Id: Copy> EntryBlock<Id> {
    fn new() -> Self {
        Self {
            ids: [None; ENTRY_BLOCK],
            rays: [Ray::new(Vec3::ZERO, Vec3::X); ENTRY_BLOCK],
            entries: Entries::new(),
            len: 0,
            next: 0,
            exhausted: false,
        }
    }
}
