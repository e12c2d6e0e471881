//! The pieces both walks share: the stack of children still to visit, the front-to-back
//! order they are pushed in, and the prefetch of every entered child.

use std::mem::MaybeUninit;

use super::WideNode;
use crate::accel::bvh::MAX_DEPTH;
use crate::accel::leaves::{Prefetch, prefetch_lines};

/// A child still to visit: what [`WideNode::child`] and [`WideNode::count`] hold for it, and
/// the ray's conservative entry distance into its box.
#[derive(Clone, Copy)]
pub(crate) struct Entry {
    pub(super) child: u32,
    pub(super) count: u32,
    pub(super) near: f32,
}

/// A fixed stack: each level of the tree pushes at most `W - 1` entries.
pub(crate) struct Stack<const N: usize> {
    items: [MaybeUninit<Entry>; N],
    len: usize,
}

impl<const N: usize> Stack<N> {
    #[inline(always)]
    pub(super) const fn new() -> Self {
        Self {
            // An array of `MaybeUninit` needs no initialisation: nothing is read before written.
            items: [const { MaybeUninit::uninit() }; N],
            len: 0,
        }
    }

    /// Drops every entry (a slot of the batch walk reused for the next ray).
    #[inline(always)]
    pub(super) fn clear(&mut self) {
        self.len = 0;
    }

    #[inline(always)]
    pub(super) fn push(&mut self, e: Entry) {
        self.items[self.len] = MaybeUninit::new(e);
        self.len += 1;
    }

    /// Writes `e` into the slot `above` places above the top, without pushing it: entries
    /// put in their order at once, then pushed together by [`Self::raise`].
    #[inline(always)]
    pub(super) fn put_above(&mut self, above: usize, e: Entry) {
        self.items[self.len + above] = MaybeUninit::new(e);
    }

    /// Pushes the `n` entries put above the top.
    ///
    /// # Safety
    /// Each of the `n` slots above the top was written by [`Self::put_above`] since the
    /// last push or pop.
    #[inline(always)]
    pub(super) unsafe fn raise(&mut self, n: usize) {
        self.len += n;
    }

    #[inline(always)]
    pub(super) fn pop(&mut self) -> Option<Entry> {
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        // SAFETY: every slot below `len` was written by `push`.
        Some(unsafe { self.items[self.len].assume_init() })
    }
}

/// Stack capacity for widths up to 8: `W - 1` entries per level below the root, plus the
/// root's `W`.
pub(crate) const STACK: usize = 7 * MAX_DEPTH + 8;

/// Starts loading every entered child of `node`: each cache line of an interior child, and
/// the leaf data of a leaf (through its tester), so the ones pushed for later are in cache by
/// the time they are popped. Measured: -4% time per ray on the 69k bunny's incoherent rays,
/// -13% on the 1.1M one's (BENCHMARKS.md, Phase 14).
#[inline(always)]
pub(super) fn prefetch_children<const W: usize>(
    nodes: &[WideNode<W>],
    node: &WideNode<W>,
    mask: u32,
    leaves: &impl Prefetch,
) {
    let mut m = mask;
    while m != 0 {
        let lane = m.trailing_zeros() as usize;
        m &= m - 1;
        match node.count[lane] {
            0 => {
                if let Some(child) = nodes.get(node.child[lane] as usize) {
                    prefetch_lines(child);
                }
            }
            count => leaves.prefetch(node.child[lane], count),
        }
    }
}

/// Pushes the entered lanes of `node` farthest first and returns the nearest, to visit next.
#[inline(always)]
pub(super) fn push_entered<const W: usize, const N: usize>(
    node: &WideNode<W>,
    mask: u32,
    near: &[f32; W],
    stack: &mut Stack<N>,
) -> Option<Entry> {
    let entry = |lane: usize| Entry {
        child: node.child[lane],
        count: node.count[lane],
        near: near[lane],
    };
    match mask.count_ones() {
        0 => None,
        1 => Some(entry(mask.trailing_zeros() as usize)),
        2 => {
            // The most common split: one comparison, no sort.
            let a = entry(mask.trailing_zeros() as usize);
            let b = entry((31 - mask.leading_zeros()) as usize);
            let (near, far) = if b.near < a.near { (b, a) } else { (a, b) };
            stack.push(far);
            Some(near)
        }
        n => {
            // Insertion sort of the few entered lanes, nearest last.
            let mut sorted = [MaybeUninit::<Entry>::uninit(); W];
            let mut m = mask;
            for i in 0..n as usize {
                let lane = m.trailing_zeros() as usize;
                m &= m - 1;
                let e = entry(lane);
                let mut j = i;
                // SAFETY: slots below `i` were written in earlier iterations.
                while j > 0 && unsafe { sorted[j - 1].assume_init() }.near < e.near {
                    sorted[j] = sorted[j - 1];
                    j -= 1;
                }
                sorted[j] = MaybeUninit::new(e);
            }
            for s in &sorted[..n as usize - 1] {
                // SAFETY: the first `n` slots were written above.
                stack.push(unsafe { s.assume_init() });
            }
            // SAFETY: as above.
            Some(unsafe { sorted[n as usize - 1].assume_init() })
        }
    }
}
