//! What a traversal does at a leaf: test its primitives. Either one at a time through a
//! closure (any accelerator, any primitive test), or a whole leaf at once by a tester that
//! keeps its own copy of the primitives in leaf order (`geometry::PackedLeaves`).

use super::{Closest, TraversalStats};
use crate::geometry::PrimHit;
use crate::math::Ray;

/// Nearest-hit tests of whole leaves: `first` is the leaf's position in the hierarchy's
/// `prim_order`, `prims` its entries there.
pub(crate) trait ClosestLeaves {
    /// Offers every hit in the leaf to `closest` (whose ray's `t_max` shrinks as it goes).
    fn closest(
        &mut self,
        first: u32,
        prims: &[u32],
        closest: &mut Closest,
        stats: &mut TraversalStats,
    );
}

/// Any-hit tests of whole leaves (see [`ClosestLeaves`]).
pub(crate) trait AnyLeaves {
    /// True at the first primitive of the leaf that blocks `ray`.
    fn any(&mut self, first: u32, prims: &[u32], ray: &Ray, stats: &mut TraversalStats) -> bool;
}

/// A closure testing one primitive, applied to a leaf's primitives in order.
pub(crate) struct PerPrim<F>(pub F);

impl<F: FnMut(u32, &Ray) -> Option<PrimHit>> ClosestLeaves for PerPrim<F> {
    #[inline(always)]
    fn closest(
        &mut self,
        _: u32,
        prims: &[u32],
        closest: &mut Closest,
        stats: &mut TraversalStats,
    ) {
        for &prim in prims {
            stats.prim_tests += 1;
            if let Some(h) = (self.0)(prim, &closest.ray) {
                closest.offer(prim, h);
            }
        }
    }
}

impl<F: FnMut(u32, &Ray) -> bool> AnyLeaves for PerPrim<F> {
    #[inline(always)]
    fn any(&mut self, _: u32, prims: &[u32], ray: &Ray, stats: &mut TraversalStats) -> bool {
        prims.iter().any(|&prim| {
            stats.prim_tests += 1;
            (self.0)(prim, ray)
        })
    }
}
