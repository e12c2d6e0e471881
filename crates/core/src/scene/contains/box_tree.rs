//! A binary hierarchy over boxes, for the point queries of containment: which items' boxes hold
//! a point (compared exactly, boundaries included), and the node structure the winding number's
//! far-field sums walk. Built by median splits on the longest axis of the box centres, the
//! same way for the same boxes (ties by item index), so answers do not depend on anything else.

use crate::math::{Aabb, Vec3};

/// Items per leaf.
const LEAF: usize = 4;

/// One node: a leaf lists `count` items from `first` in [`BoxTree::items`]; an inner node
/// (`count == 0`) has its children at the next index and at `first`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Node {
    /// The union of its items' boxes.
    pub bounds: Aabb,
    pub first: u32,
    pub count: u32,
}

impl Node {
    /// The children of an inner node, `None` for a leaf.
    pub fn children(&self, index: usize) -> Option<[usize; 2]> {
        (self.count == 0).then_some([index + 1, self.first as usize])
    }
}

/// The hierarchy: nodes in depth-first order (a node before its descendants) and the item
/// ids in leaf order.
#[derive(Clone, Debug, Default)]
pub(super) struct BoxTree {
    pub nodes: Vec<Node>,
    pub items: Vec<u32>,
}

/// True when `p` lies in `b`, boundaries included.
#[inline]
pub(super) fn holds(b: &Aabb, p: Vec3) -> bool {
    p.cmpge(b.min).all() && p.cmple(b.max).all()
}

impl BoxTree {
    /// The hierarchy over the items `ids` with boxes `boxes[id]` (empty boxes left out).
    pub fn build(boxes: &[Aabb], ids: impl IntoIterator<Item = u32>) -> Self {
        let mut items: Vec<u32> = ids
            .into_iter()
            .filter(|&i| !boxes[i as usize].is_empty())
            .collect();
        let mut tree = BoxTree {
            nodes: Vec::with_capacity(2 * items.len().div_ceil(LEAF)),
            items: Vec::new(),
        };
        if !items.is_empty() {
            tree.split(boxes, &mut items, 0);
        }
        tree.items = items;
        tree
    }

    /// Adds the node over `items` (starting at `offset` in the final order) and its subtree.
    fn split(&mut self, boxes: &[Aabb], items: &mut [u32], offset: usize) {
        let bounds = items
            .iter()
            .fold(Aabb::EMPTY, |b, &i| b.union(boxes[i as usize]));
        let index = self.nodes.len();
        self.nodes.push(Node {
            bounds,
            first: offset as u32,
            count: items.len() as u32,
        });
        if items.len() <= LEAF {
            return;
        }
        let centre = |i: u32| boxes[i as usize].center();
        let spread = items
            .iter()
            .fold(Aabb::EMPTY, |b, &i| b.grow(centre(i)))
            .extent();
        let axis = if spread.x >= spread.y && spread.x >= spread.z {
            0
        } else if spread.y >= spread.z {
            1
        } else {
            2
        };
        let mid = items.len() / 2;
        items.select_nth_unstable_by(mid, |&a, &b| {
            centre(a)[axis].total_cmp(&centre(b)[axis]).then(a.cmp(&b))
        });
        let (left, right) = items.split_at_mut(mid);
        self.split(boxes, left, offset);
        let right_index = self.nodes.len() as u32;
        self.split(boxes, right, offset + mid);
        self.nodes[index].first = right_index;
        self.nodes[index].count = 0;
    }

    /// True when `test` holds for some item of a leaf whose box holds `p` (a superset of the
    /// items whose own boxes hold it: `test` checks those itself); items are tried in a fixed
    /// order, up to the first yes.
    pub fn any_near(&self, p: Vec3, mut test: impl FnMut(u32) -> bool) -> bool {
        let mut stack = Vec::with_capacity(32);
        if !self.nodes.is_empty() {
            stack.push(0);
        }
        while let Some(i) = stack.pop() {
            let node = &self.nodes[i];
            if !holds(&node.bounds, p) {
                continue;
            }
            match node.children(i) {
                Some([l, r]) => stack.extend([r, l]),
                None => {
                    let leaf = &self.items[node.first as usize..][..node.count as usize];
                    for &item in leaf {
                        if test(item) {
                            return true;
                        }
                    }
                }
            }
        }
        false
    }

    /// Calls `visit` with every item of a leaf whose box holds `p`, in a fixed order.
    pub fn for_each_near(&self, p: Vec3, mut visit: impl FnMut(u32)) {
        self.any_near(p, |item| {
            visit(item);
            false
        });
    }
}
