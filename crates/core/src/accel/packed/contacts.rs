//! The all-hits query's leaf test over packed leaves: every contact of the ray with a leaf's
//! primitives, as [`Geometry::contacts`] gives it, bit for bit, with four triangles decided at
//! once.
//!
//! A lane the SIMD pass finds a clean hit on the triangle's line has three certain edge signs
//! that agree, and certain signs are the exact ones, so no exact edge function is zero: the
//! touch is a crossing, with no exact re-evaluation (what most hits are). Every other candidate
//! lane goes through the scalar triangle test and [`triangle_contact`], or through the
//! geometry's own contacts when it holds no triangle, exactly as the per-primitive path.

use super::{LANES, NO_SLOT, PackedLeaves, PackedWatertight, group_corners};
use crate::accel::leaves::{AnyLeaves, Prefetch};
use crate::accel::{PADDING, TraversalStats};
use crate::geometry::crossing::triangle_contact;
use crate::geometry::triangle::{WatertightRay, finish_decided_hit, intersect_triangle};
use crate::geometry::{Contact, Geometry, Precision, Primitive, Touch};
use crate::math::Ray;

/// Collects the contacts of every leaf the walk enters (an any-hit walk that never stops).
pub(crate) struct PackedContacts<'a, 'o> {
    test: PackedWatertight<'a>,
    /// The query's precision, for the primitives that are not triangles (the triangles'
    /// test is the watertight one for every precision but `Double`, which does not come here).
    precision: Precision,
    out: &'o mut Vec<Contact>,
    /// The slot of each contact in the leaf order ([`NO_SLOT`] for one that is not a
    /// triangle's): a contact's normal is then read from there, as the nearest hit's.
    slots: &'o mut Vec<u32>,
}

impl<'a, 'o> PackedContacts<'a, 'o> {
    /// Contacts with the primitives of `packed` (built from `geometry`) pushed onto `out`.
    #[inline(always)]
    pub(crate) fn new(
        packed: &'a PackedLeaves,
        geometry: &'a Geometry,
        precision: Precision,
        out: &'o mut Vec<Contact>,
        slots: &'o mut Vec<u32>,
    ) -> Self {
        debug_assert!(precision != Precision::Double);
        Self {
            test: PackedWatertight::new(packed, geometry),
            precision,
            out,
            slots,
        }
    }

    /// Pushes the contacts of the leaf at `first` with `count` entries.
    #[inline(always)]
    fn leaf(&mut self, first: u32, count: usize, ray: &Ray) {
        let geometry = self.test.geometry;
        let (wr, test) = self.test.shear.get_or_insert_with(|| {
            let wr = WatertightRay::new(ray.dir);
            (wr, super::GroupTest::new(ray, &wr))
        });
        let mut left = count;
        let mut g = first as usize / LANES;
        while left > 0 {
            let lanes = left.min(LANES);
            let group = &self.test.packed.groups[g];
            let decided = test.decide(group, (1 << lanes) - 1);
            let mut mask = decided.line_hits | decided.scalar;
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let prim = group.prim[lane];
                if group.v[0][lane].is_nan() {
                    // Not a triangle: a sphere or an instance, through its own contacts.
                    if prim != PADDING {
                        geometry.contacts(prim, ray, wr, self.precision, self.out);
                        self.slots.resize(self.out.len(), NO_SLOT);
                    }
                    continue;
                }
                let p = group_corners(&group.v, lane);
                let slot = (g * LANES + lane) as u32;
                if decided.line_hits & (1 << lane) != 0 {
                    match finish_decided_hit(ray, p, decided.u[lane], decided.v[lane]) {
                        Ok(None) => continue,
                        Ok(Some(h)) => {
                            if geometry.alpha_passes(prim, h.u, h.v) {
                                self.out.push(Contact {
                                    prim,
                                    hit: h.into(),
                                    touch: Touch::Crossing,
                                });
                                self.slots.push(slot);
                            }
                            continue;
                        }
                        // The plane form failed: the scalar test finishes, as it does there.
                        Err(()) => {}
                    }
                }
                let Some(h) = intersect_triangle(ray, wr, p[0], p[1], p[2]) else {
                    continue;
                };
                if !geometry.alpha_passes(prim, h.u, h.v) {
                    continue;
                }
                if let Primitive::Triangle { mesh, .. } = geometry.prims()[prim as usize]
                    && let Some(c) = triangle_contact(prim, h.into(), ray, wr, p, mesh)
                {
                    self.out.push(c);
                    self.slots.push(slot);
                }
            }
            left -= lanes;
            g += 1;
        }
    }
}

impl Prefetch for PackedContacts<'_, '_> {
    #[inline(always)]
    fn prefetch(&self, first: u32, count: u32) {
        self.test.prefetch(first, count);
    }
}

impl AnyLeaves for PackedContacts<'_, '_> {
    #[inline(always)]
    fn any(&mut self, first: u32, prims: &[u32], ray: &Ray, stats: &mut TraversalStats) -> bool {
        stats.prim_tests += prims.len() as u64;
        self.leaf(first, prims.len(), ray);
        false
    }
}
