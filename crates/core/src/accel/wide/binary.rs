//! The binary tree inside each wide node, kept as a 15-bit shape so the wide hierarchy can give
//! back exactly the binary tree it was collapsed from (the paper's traversals walk binary nodes).
//!
//! A shape is the preorder of the binary subtree a wide node was opened from, one bit per node
//! from the least significant bit: 1 for an opened (interior) node, 0 for a lane. Lanes are
//! numbered in the order their 0 bits appear, which is the order [`shape_of`] gives them in.
//! A subtree with `W <= 8` lanes has `W - 1` interior nodes, so `2W - 1 <= 15` bits.

use super::lanes::Lanes;
use super::{WideBvh, WideNode};
use crate::accel::bvh::{Bvh, Node};
use crate::math::Aabb;

/// The shape of a wide node holding one lane and no split (a root that is a leaf).
pub(super) const SINGLE_LANE: u16 = 0;

/// The shape of the binary subtree at `root` in which the nodes `opened` were opened, and its
/// lanes (binary node indices) in left-to-right order.
pub(super) fn shape_of(bin: &[Node], root: u32, opened: &[u32]) -> (u16, Lanes<u32>) {
    let (mut shape, mut bit) = (0u16, 0);
    let mut lanes: Option<Lanes<u32>> = None;
    let mut stack = Lanes::new(root);
    while let Some(n) = stack.pop() {
        if opened.contains(&n) {
            shape |= 1 << bit;
            let first = bin[n as usize].first;
            stack.push(first + 1);
            stack.push(first);
        } else if let Some(l) = &mut lanes {
            l.push(n);
        } else {
            lanes = Some(Lanes::new(n));
        }
        bit += 1;
    }
    (shape, lanes.expect("a subtree has a lane"))
}

impl<const W: usize> WideBvh<W> {
    /// The binary tree this was collapsed from: the same nodes, boxes and leaves (in another
    /// array order), over the same `prim_order`.
    pub fn to_binary(&self) -> Bvh {
        if self.nodes.is_empty() {
            return Bvh::from_parts(Vec::new(), Vec::new());
        }
        let mut nodes = vec![EMPTY_NODE];
        self.unfold(0, &mut nodes, 0);
        Bvh::from_parts(nodes, self.prim_order.clone())
    }

    /// Writes the binary subtree of wide node `w` with its root at `nodes[at]`.
    fn unfold(&self, w: u32, nodes: &mut Vec<Node>, at: usize) {
        let node = &self.nodes[w as usize];
        let (mut bit, mut lane) = (0, 0);
        self.unfold_shape(
            node,
            self.shapes[w as usize],
            &mut bit,
            &mut lane,
            nodes,
            at,
        );
    }

    /// Reads one binary node of `shape` from `bit` into `nodes[at]`; returns its bounds.
    fn unfold_shape(
        &self,
        node: &WideNode<W>,
        shape: u16,
        bit: &mut u32,
        lane: &mut usize,
        nodes: &mut Vec<Node>,
        at: usize,
    ) -> Aabb {
        let interior = shape >> *bit & 1 == 1;
        *bit += 1;
        if interior {
            let first = nodes.len();
            nodes.extend([EMPTY_NODE, EMPTY_NODE]);
            let l = self.unfold_shape(node, shape, bit, lane, nodes, first);
            let r = self.unfold_shape(node, shape, bit, lane, nodes, first + 1);
            let bounds = l.union(r);
            nodes[at] = Node {
                bounds,
                first: first as u32,
                count: 0,
            };
            return bounds;
        }
        let i = *lane;
        *lane += 1;
        let bounds = node.bounds(i);
        if node.count[i] == 0 {
            self.unfold(node.child[i], nodes, at);
        } else {
            nodes[at] = Node {
                bounds,
                first: node.child[i],
                count: node.count[i],
            };
        }
        bounds
    }
}

const EMPTY_NODE: Node = Node {
    bounds: Aabb::EMPTY,
    first: 0,
    count: 0,
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::test_boxes::scattered;
    use crate::accel::{BuildOptions, sah};

    /// Every node of a binary tree as (bounds, leaf primitives in order), sorted.
    fn contents(b: &Bvh) -> Vec<String> {
        let mut all: Vec<String> = b
            .nodes()
            .iter()
            .map(|n| {
                let prims = if n.is_leaf() {
                    b.leaf_prims(n).to_vec()
                } else {
                    vec![]
                };
                format!("{:?} {prims:?}", n.bounds)
            })
            .collect();
        all.sort();
        all
    }

    #[test]
    fn unfolding_gives_back_the_binary_tree() {
        for (n, leaf) in [(1, 4), (2, 1), (7, 4), (300, 1), (2000, 4), (2000, 20)] {
            let bounds = scattered(n, 0);
            let binary = sah::build(
                &bounds,
                &[],
                &BuildOptions {
                    max_leaf_size: leaf,
                    ..Default::default()
                },
            );
            let wide = WideBvh::<8>::collapse(&binary);
            wide.validate(&bounds).unwrap();
            let back = wide.to_binary();
            back.validate(&bounds).unwrap();
            assert_eq!(
                contents(&back),
                contents(&binary),
                "{n} boxes, leaves of {leaf}"
            );
        }
    }
}
