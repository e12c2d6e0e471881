//! The rays of a batch query ([`Accel::trace_geometry_each`]) as the batch walk
//! (`wide::in_flight`) asks for them: the next ray, its answer, and the instances it enters.

use super::PackedWatertight;
use super::wide::{Entered, Inside, NearestQueries, NearestStack, inside};
use super::{Accel, Hit, PackedLeaves, PrimHit, Traced, TraversalStats};
use crate::geometry::{Geometry, Precision};
use crate::math::Ray;

/// The rays of [`Accel::trace_geometry_each`] through the packed leaves: those the frame
/// holds go to the batch walk, the others are traced on the way, as `trace_geometry` would.
/// `ENTERS`: the geometry has instances, which the batch walk enters in place.
pub(super) struct PackedQueries<'a, R, A, const ENTERS: bool> {
    accel: &'a Accel,
    geometry: &'a Geometry,
    packed: &'a PackedLeaves,
    rays: R,
    answer: A,
}

impl<'a, R, A, const ENTERS: bool> PackedQueries<'a, R, A, ENTERS> {
    /// The rays of `rays`, answered to `answer`, through the accelerator, shapes and packed
    /// leaves of `parts`.
    #[inline(always)]
    pub(super) fn new(
        (accel, geometry, packed): (&'a Accel, &'a Geometry, &'a PackedLeaves),
        rays: R,
        answer: A,
    ) -> Self {
        Self {
            accel,
            geometry,
            packed,
            rays,
            answer,
        }
    }
}

impl<'a, Id, R, A, const ENTERS: bool> NearestQueries<'a> for PackedQueries<'a, R, A, ENTERS>
where
    Id: Copy,
    R: FnMut() -> Option<(Id, Ray)>,
    A: FnMut(Id, Option<Traced>),
{
    type Id = Id;
    type Leaves = PackedWatertight<'a>;
    const ENTERS_INSTANCES: bool = ENTERS;

    #[inline(always)]
    fn next(&mut self, stats: &mut TraversalStats) -> Option<(Id, Ray, PackedWatertight<'a>)> {
        loop {
            let (id, ray) = (self.rays)()?;
            if self.accel.frame.holds(ray.origin) {
                let leaves = if ENTERS {
                    PackedWatertight::entering_instances(self.packed, self.geometry)
                } else {
                    PackedWatertight::new(self.packed, self.geometry)
                };
                return Some((id, ray, leaves));
            }
            let far = self
                .accel
                .trace_far(self.geometry, Precision::Watertight, &ray, stats);
            (self.answer)(id, far);
        }
    }

    #[inline(always)]
    fn answer(&mut self, id: Id, ray: &Ray, hit: Option<Hit>, leaves: &PackedWatertight<'a>) {
        // As `trace_geometry` answers a ray the frame holds.
        let traced = hit.map(|h| Traced::on(ray, (h, leaves.best_slot()), h.hit.t));
        (self.answer)(id, traced);
    }

    #[inline(always)]
    fn enter(
        &self,
        leaves: &mut PackedWatertight<'a>,
        ray: &Ray,
        stack: &mut NearestStack,
        walk: &mut Option<Inside<'a>>,
    ) -> Option<Entered> {
        let (prim, instance) = leaves.next_instance()?;
        Some(inside::enter(
            self.geometry,
            prim,
            instance,
            ray,
            stack,
            walk,
        ))
    }

    #[inline(always)]
    fn leave(&self, inside: &Inside<'a>) -> Option<(u32, PrimHit, Option<u32>)> {
        inside.answer()
    }

    #[inline(always)]
    fn took_entered(leaves: &mut PackedWatertight<'a>, slot: Option<u32>) {
        leaves.took_entered(slot);
    }

    #[inline(always)]
    fn alone(leaves: &mut PackedWatertight<'a>) {
        leaves.test_instances();
    }
}
