//! A wide bounding-volume hierarchy: the binary SAH tree collapsed into nodes of `W` children
//! whose boxes are stored structure-of-arrays, so one SIMD slab test decides all of them at
//! once. The renderer uses `W = 8` with AVX2 or AVX-512 as the CPU has ([`SimdPath`]; 4 lanes
//! with SSE measured slower, BENCHMARKS.md);
//! the collapse, validation and lane-by-lane test are written for any width up to 8.
//!
//! A child lane is an interior node (index into `nodes`), a leaf (a range of `prim_order`), or
//! unused (an empty box that no finite ray enters). The leaves are the binary tree's leaves,
//! unchanged, so the primitives a ray reaches are the same; only the boxes visited on the way
//! differ, and they are culled with the same conservative bound as the binary traversal
//! ([`super::bvh::CullBound`]), which keeps every answer identical to brute force.

#[cfg(target_arch = "x86_64")]
mod avx512;
mod binary;
mod child_test;
mod every_leaf;
mod in_flight;
pub(crate) mod inside;
mod lanes;
mod nearest;
mod opening;
mod packet;
mod simd_path;
mod traverse;
mod walk;

pub(crate) use every_leaf::LevelQueue;
pub(crate) use in_flight::NearestQueries;
pub(crate) use inside::{Entered, Inside};
pub(crate) use nearest::NearestStack;

pub use packet::PACKET;
pub use simd_path::SimdPath;

use super::bvh::{Bvh, MAX_DEPTH, Node, each_once, leaf_content};
use crate::math::{Aabb, Vec3};
use opening::Openings;

/// Marks an unused child lane in [`WideNode::count`].
pub(crate) const EMPTY_LANE: u32 = u32::MAX;

/// Every leaf starts at a multiple of this in `prim_order`, so leaf data laid out in groups
/// of this many primitives (see `geometry::TrianglePack`) is found by `first / LEAF_ALIGN`.
pub const LEAF_ALIGN: usize = 4;

/// Fills the `prim_order` gaps that align the leaves; never inside a leaf's range.
pub const PADDING: u32 = u32::MAX;

/// One node: the boxes of up to `W` children, one array per box plane.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub struct WideNode<const W: usize> {
    /// `[min x, max x, min y, max y, min z, max z]`, one lane per child. Unused lanes hold the
    /// empty box (`min = +inf`, `max = -inf`).
    pub(crate) planes: [[f32; W]; 6],
    /// Interior child: its node index. Leaf: its first entry in `prim_order`.
    pub(crate) child: [u32; W],
    /// Leaf: its primitive count (> 0). Interior: 0. Unused: [`EMPTY_LANE`].
    pub(crate) count: [u32; W],
}

impl<const W: usize> WideNode<W> {
    const UNUSED: Self = Self {
        planes: [
            [f32::INFINITY; W],
            [f32::NEG_INFINITY; W],
            [f32::INFINITY; W],
            [f32::NEG_INFINITY; W],
            [f32::INFINITY; W],
            [f32::NEG_INFINITY; W],
        ],
        child: [0; W],
        count: [EMPTY_LANE; W],
    };

    /// The box of lane `i`.
    #[inline(always)]
    pub(crate) fn bounds(&self, i: usize) -> Aabb {
        let p = &self.planes;
        Aabb {
            min: Vec3::new(p[0][i], p[2][i], p[4][i]),
            max: Vec3::new(p[1][i], p[3][i], p[5][i]),
        }
    }

    fn set(&mut self, i: usize, bounds: &Aabb, child: u32, count: u32) {
        for axis in 0..3 {
            self.planes[2 * axis][i] = bounds.min[axis];
            self.planes[2 * axis + 1][i] = bounds.max[axis];
        }
        self.child[i] = child;
        self.count[i] = count;
    }
}

/// A built wide hierarchy. Node 0 is the root; `bounds` is the root's box.
#[derive(Clone, Debug)]
pub struct WideBvh<const W: usize> {
    nodes: Vec<WideNode<W>>,
    /// Per node, the binary subtree its lanes were collapsed from (see [`binary`]), so the
    /// binary tree can be given back to the paper's traversals without being kept.
    shapes: Vec<u16>,
    prim_order: Vec<u32>,
    bounds: Aabb,
}

/// The width the renderer uses: 8 lanes, one AVX2 register per plane (see BENCHMARKS.md for
/// the 4-against-8 measurement).
pub type Wide8 = WideBvh<8>;

impl<const W: usize> WideBvh<W> {
    /// Collapses a binary hierarchy: each wide node opens binary nodes below its own until it
    /// has up to `W` lanes, chosen over the whole tree for the least cost by the surface area
    /// heuristic with a price per wide node ([`opening`]).
    pub fn collapse(binary: &Bvh) -> Self {
        const {
            assert!(
                W >= 2 && W <= 8,
                "the traversal stack and masks are sized for 8 lanes"
            )
        };
        let bin = binary.nodes();
        let mut wide = Self {
            // At most one wide node per binary interior node (about a third of that in
            // practice): room never written is address space only, and an exact upper bound
            // means the nodes never move out of their huge pages.
            nodes: crate::huge_pages::vec_with_capacity(bin.len() / 2 + 1),
            shapes: Vec::with_capacity(bin.len() / 6 + 1),
            prim_order: Vec::with_capacity(binary.prim_order().len() * 5 / 4),
            bounds: bin.first().map_or(Aabb::EMPTY, |n| n.bounds),
        };
        match bin.first() {
            None => {}
            Some(root) if root.is_leaf() => {
                let mut node = WideNode::UNUSED;
                let first = wide.place_leaf(binary, root);
                node.set(0, &root.bounds, first, root.count);
                wide.nodes.push(node);
                wide.shapes.push(binary::SINGLE_LANE);
            }
            Some(_) => {
                wide.emit(binary, &Openings::new(bin), 0);
            }
        }
        let len = wide.prim_order.len().next_multiple_of(LEAF_ALIGN);
        wide.prim_order.resize(len, PADDING);
        wide
    }

    /// Copies a binary leaf's primitives to the next aligned position; returns where it starts.
    fn place_leaf(&mut self, binary: &Bvh, leaf: &Node) -> u32 {
        let aligned = self.prim_order.len().next_multiple_of(LEAF_ALIGN);
        self.prim_order.resize(aligned, PADDING);
        // A loop, not a slice copy: leaves hold a handful of primitives, fewer than a call
        // to `memcpy` costs.
        for &p in binary.leaf_prims(leaf) {
            self.prim_order.push(p);
        }
        aligned as u32
    }

    /// Appends the wide node for binary interior node `index`, then its subtrees; returns its index.
    fn emit(&mut self, binary: &Bvh, openings: &Openings<W>, index: u32) -> u32 {
        let bin = binary.nodes();
        let at = self.nodes.len();
        self.nodes.push(WideNode::UNUSED);
        self.shapes.push(0);
        let opened = openings.opened(bin, index);
        // Lanes in the binary subtree's left-to-right order, and its shape.
        let (shape, lanes) = binary::shape_of(bin, index, opened.as_slice());
        self.shapes[at] = shape;
        for (lane, &k) in lanes.as_slice().iter().enumerate() {
            let n = &bin[k as usize];
            let (child, count) = if n.is_leaf() {
                (self.place_leaf(binary, n), n.count)
            } else {
                (self.emit(binary, openings, k), 0)
            };
            self.nodes[at].set(lane, &n.bounds, child, count);
        }
        at as u32
    }

    /// The nodes, root first.
    pub fn nodes(&self) -> &[WideNode<W>] {
        &self.nodes
    }

    /// Primitive indices in leaf order, each leaf starting at a multiple of [`LEAF_ALIGN`]
    /// ([`PADDING`] in the gaps).
    pub fn prim_order(&self) -> &[u32] {
        &self.prim_order
    }

    /// Bytes of the hierarchy (nodes, shapes and primitive order), for the bytes-per-primitive
    /// figure.
    pub fn bytes(&self) -> usize {
        self.node_bytes() + 4 * self.prim_order.len()
    }

    /// Bytes of the nodes and of their shapes.
    pub fn node_bytes(&self) -> usize {
        std::mem::size_of_val(self.nodes.as_slice()) + std::mem::size_of_val(self.shapes.as_slice())
    }

    /// The surface area heuristic's cost of a ray through the tree, in SIMD tests: a node's
    /// box test for every node, plus one test per group of [`LEAF_ALIGN`] primitives for every
    /// leaf, each weighted by the chance that a ray crossing the root crosses the box that leads
    /// to it (its area over the root's). The measure builders are compared by.
    pub fn sah_cost(&self) -> f64 {
        let area = |b: Aabb| {
            let e = (b.max - b.min).max(Vec3::ZERO).as_dvec3();
            e.x * e.y + e.y * e.z + e.z * e.x
        };
        let root = area(self.bounds);
        if self.nodes.is_empty() || root <= 0.0 {
            return 0.0;
        }
        let mut cost = root;
        for node in &self.nodes {
            for lane in 0..W {
                let tests = match node.count[lane] {
                    EMPTY_LANE => continue,
                    0 => 1,
                    n => (n as usize).div_ceil(LEAF_ALIGN),
                };
                cost += area(node.bounds(lane)) * tests as f64;
            }
        }
        cost / root
    }

    /// Checks the invariants: every primitive reached exactly once, every lane's box exactly
    /// the union of what it holds, depth within the traversal stack. Returns the first violation.
    pub fn validate(&self, prim_bounds: &[Aabb]) -> Result<(), String> {
        if self.nodes.is_empty() {
            return if prim_bounds.is_empty() {
                Ok(())
            } else {
                Err("no nodes for primitives".into())
            };
        }
        if !self.prim_order.len().is_multiple_of(LEAF_ALIGN) {
            return Err(format!(
                "the leaf order's {} entries do not fill whole groups",
                self.prim_order.len()
            ));
        }
        let mut seen = vec![0u32; prim_bounds.len()];
        let content = self.validate_node(0, 1, prim_bounds, &mut seen)?;
        if content != self.bounds {
            return Err(format!("root bounds {:?} are not tight", self.bounds));
        }
        each_once(&seen)
    }

    fn validate_node(
        &self,
        index: u32,
        depth: usize,
        prim_bounds: &[Aabb],
        seen: &mut [u32],
    ) -> Result<Aabb, String> {
        if depth > MAX_DEPTH {
            return Err(format!(
                "node {index} at depth {depth} exceeds the stack budget"
            ));
        }
        let node = self
            .nodes
            .get(index as usize)
            .ok_or(format!("node {index} out of range"))?;
        let mut all = Aabb::EMPTY;
        for lane in 0..W {
            let (child, count) = (node.child[lane], node.count[lane]);
            let content = match count {
                EMPTY_LANE => Aabb::EMPTY,
                0 if child <= index => {
                    return Err(format!(
                        "node {index}: child {child} does not come after it"
                    ));
                }
                0 => self.validate_node(child, depth + 1, prim_bounds, seen)?,
                _ => {
                    let range = child as usize..(child + count) as usize;
                    if !range.start.is_multiple_of(LEAF_ALIGN) {
                        return Err(format!("node {index} lane {lane}: leaf is not aligned"));
                    }
                    let prims = self
                        .prim_order
                        .get(range)
                        .ok_or(format!("node {index} lane {lane}: leaf out of range"))?;
                    leaf_content(prims, prim_bounds, seen)
                        .map_err(|e| format!("node {index} lane {lane}: {e}"))?
                }
            };
            if content != node.bounds(lane) {
                return Err(format!("node {index} lane {lane}: bounds are not tight"));
            }
            all = all.union(content);
        }
        Ok(all)
    }
}
