//! What a traversal does at a leaf: test its primitives. Either one at a time through a
//! closure (any accelerator, any primitive test), or a whole leaf at once by a tester that
//! keeps its own copy of the primitives in leaf order (`geometry::PackedLeaves`).

use super::{Closest, TraversalStats};
use crate::geometry::PrimHit;
use crate::math::Ray;

/// Starting to load a leaf's data ahead of its test (see the wide walk's prefetching).
pub(crate) trait Prefetch {
    /// The leaf at `first` with `count` entries will probably be tested soon.
    #[inline(always)]
    fn prefetch(&self, _first: u32, _count: u32) {}
}

/// Asks for every cache line `value` touches to be loaded, without waiting for it. One prefetch
/// per 64 bytes from its start reaches every line only when no placement the type's alignment
/// allows makes it straddle one more line (a 160-byte leaf group aligned to 16 bytes can touch
/// four lines, so the groups are aligned to 32); checked at compile time.
#[inline(always)]
pub(crate) fn prefetch_lines<T>(value: &T) {
    const {
        let (size, align) = (size_of::<T>(), align_of::<T>());
        let worst_offset = 64_usize.saturating_sub(align);
        assert!(worst_offset + size <= size.div_ceil(64) * 64);
    }
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let p = (value as *const T).cast::<i8>();
        for line in (0..size_of::<T>()).step_by(64) {
            // SAFETY: a prefetch reads nothing and cannot fault; the address lies inside `value`.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(line)) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}

/// Nearest-hit tests of whole leaves: `first` is the leaf's position in the hierarchy's
/// `prim_order`, `prims` its entries there.
pub(crate) trait ClosestLeaves: Prefetch {
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
pub(crate) trait AnyLeaves: Prefetch {
    /// True at the first primitive of the leaf that blocks `ray`.
    fn any(&mut self, first: u32, prims: &[u32], ray: &Ray, stats: &mut TraversalStats) -> bool;
}

/// A closure testing one primitive, applied to a leaf's primitives in order.
pub(crate) struct PerPrim<F>(pub F);

impl<F> Prefetch for PerPrim<F> {}

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
