//! Which binary nodes each wide node opens. Every binary leaf ends up a lane of some wide node
//! and costs the same wherever it lands; what the choice changes is which interior binary nodes
//! become wide nodes of their own, and each such node costs a ray crossing its box one more
//! node test ([`super::WideBvh::sah_cost`]) and 256 bytes. Opening the largest child first, node
//! by node, leaves many small subtrees near the leaves as wide nodes of two or three lanes; here
//! the choice minimises the areas of all wide nodes plus a fixed cost per node over the whole
//! tree, by dynamic programming over the binary tree (after Ylitie, Karras and Laine, "Efficient
//! incoherent ray traversal on GPUs through compressed wide BVHs", 2017).

use super::lanes::Lanes;
use crate::accel::bvh::Node;

/// The cost of one more wide node, in units of the average leaf's surface area: the memory a
/// node takes priced as a test of a box somewhat larger than a leaf's.
const NODE_COST: f32 = 1.0;

/// Per binary node `n` and lane budget `k` (1 to `W`), the least cost of the subtree at `n`
/// as at most `k` lanes of the wide node above it: `cost[n][k - 1]`.
pub(super) struct Openings<const W: usize> {
    cost: Vec<[f32; 8]>,
}

impl<const W: usize> Openings<W> {
    /// The costs over binary nodes `bin` (children after their parents, as the builders lay
    /// them out).
    pub fn new(bin: &[Node]) -> Self {
        let leaves = bin.iter().filter(|n| n.is_leaf());
        let (count, area) = leaves.fold((0usize, 0.0f64), |(c, a), n| {
            (c + 1, a + n.bounds.surface_area() as f64)
        });
        let node_cost = NODE_COST * (area / count.max(1) as f64) as f32;
        let mut cost = vec![[0.0f32; 8]; bin.len()];
        for n in (0..bin.len()).rev() {
            let node = &bin[n];
            if node.is_leaf() {
                continue;
            }
            let (l, r) = (node.first as usize, node.first as usize + 1);
            debug_assert!(l > n, "children come after their parent");
            let split = |k: usize| Self::best_split(&cost[l], &cost[r], k).1;
            // As one lane: a wide node of its own, its box tested to enter it.
            let mut c = [0.0f32; 8];
            c[0] = node.bounds.surface_area() + node_cost + split(W);
            for k in 2..=W {
                c[k - 1] = c[k - 2].min(split(k));
            }
            cost[n] = c;
        }
        Self { cost }
    }

    /// The split of `k` lanes between two children with costs `l` and `r` that costs least
    /// (of equal ones, the fewest lanes left): (lanes to the left, cost).
    #[inline(always)]
    fn best_split(l: &[f32; 8], r: &[f32; 8], k: usize) -> (usize, f32) {
        let mut best = (1, l[0] + r[k - 2]);
        for i in 2..k {
            let c = l[i - 1] + r[k - i - 1];
            if c < best.1 {
                best = (i, c);
            }
        }
        best
    }

    /// The binary nodes the wide node at interior node `root` opens, `root` first.
    pub fn opened(&self, bin: &[Node], root: u32) -> Lanes<u32> {
        let mut opened = Lanes::new(root);
        let mut todo: Lanes<(u32, usize)> = Lanes::new((root, W));
        let mut first = true;
        while let Some((n, mut k)) = todo.pop() {
            let node = &bin[n as usize];
            if node.is_leaf() {
                continue;
            }
            let cost = &self.cost[n as usize];
            if !first {
                // The fewest lanes that reach the least cost; one lane: not opened.
                while k > 1 && cost[k - 1] == cost[k - 2] {
                    k -= 1;
                }
                if k == 1 {
                    continue;
                }
                opened.push(n);
            }
            first = false;
            let (l, r) = (node.first, node.first + 1);
            let (left, _) = Self::best_split(&self.cost[l as usize], &self.cost[r as usize], k);
            todo.push((l, left));
            todo.push((r, k - left));
        }
        opened
    }
}

#[cfg(test)]
mod tests {
    use super::NODE_COST;
    use crate::accel::bvh::Node;
    use crate::accel::test_boxes::scattered;
    use crate::accel::wide::{EMPTY_LANE, WideBvh};
    use crate::accel::{BuildOptions, sah};

    /// The price of one wide node, as [`Openings::new`] sets it.
    fn node_cost(bin: &[Node]) -> f64 {
        let leaves: Vec<&Node> = bin.iter().filter(|n| n.is_leaf()).collect();
        let area: f64 = leaves.iter().map(|n| n.bounds.surface_area() as f64).sum();
        (NODE_COST * (area / leaves.len() as f64) as f32) as f64
    }

    /// The least cost over every choice of which interior binary nodes become wide nodes
    /// (the root always): each wide node's lanes must fit in `w`.
    fn cheapest_by_enumeration(bin: &[Node], w: usize) -> f64 {
        let interior: Vec<usize> = (1..bin.len()).filter(|&i| !bin[i].is_leaf()).collect();
        assert!(interior.len() <= 16);
        let price = node_cost(bin);
        let mut best = f64::INFINITY;
        for mask in 0u32..1 << interior.len() {
            let mut root = vec![false; bin.len()];
            root[0] = true;
            for (b, &i) in interior.iter().enumerate() {
                root[i] = mask >> b & 1 == 1;
            }
            let fits = (0..bin.len()).filter(|&r| root[r]).all(|r| {
                // The lanes of the wide node at r: its open descendants' children that are
                // leaves or wide nodes.
                let (mut lanes, mut todo) = (0, vec![bin[r].first, bin[r].first + 1]);
                while let Some(k) = todo.pop() {
                    let n = &bin[k as usize];
                    if n.is_leaf() || root[k as usize] {
                        lanes += 1;
                    } else {
                        todo.extend([n.first, n.first + 1]);
                    }
                }
                lanes <= w
            });
            if fits {
                let cost: f64 = (1..bin.len())
                    .filter(|&r| root[r])
                    .map(|r| bin[r].bounds.surface_area() as f64 + price)
                    .sum();
                best = best.min(cost);
            }
        }
        best
    }

    /// The cost of the wide nodes below the root of a collapsed tree.
    fn cost_of<const W: usize>(wide: &WideBvh<W>, price: f64) -> f64 {
        let nodes = wide.nodes();
        let areas: f64 = nodes
            .iter()
            .flat_map(|node| {
                (0..W)
                    .filter(|&l| node.count[l] == 0)
                    .map(|l| node.bounds(l))
            })
            .map(|b| b.surface_area() as f64)
            .sum();
        areas + price * (nodes.len() - 1) as f64
    }

    /// On trees small enough to try every choice, the collapse finds the cheapest one.
    #[test]
    fn the_choice_is_the_cheapest_of_all() {
        for seed in 0..12 {
            let bounds = scattered(14, seed);
            let binary = sah::build(
                &bounds,
                &[],
                &BuildOptions {
                    max_leaf_size: 1,
                    ..Default::default()
                },
            );
            let bin = binary.nodes();
            let price = node_cost(bin);
            let (four, eight) = (
                WideBvh::<4>::collapse(&binary),
                WideBvh::<8>::collapse(&binary),
            );
            four.validate(&bounds).unwrap();
            eight.validate(&bounds).unwrap();
            for (w, got) in [(4, cost_of(&four, price)), (8, cost_of(&eight, price))] {
                let best = cheapest_by_enumeration(bin, w);
                assert!(
                    (got - best).abs() <= 1e-4 * best.max(1.0),
                    "seed {seed}, {w} lanes: {got} against the cheapest {best}"
                );
            }
        }
    }

    /// Lanes in use per wide node: opening the largest child first left 4.5 of 8 on the
    /// bunny; the whole-tree choice fills most nodes.
    #[test]
    fn wide_nodes_are_mostly_full() {
        for (n, seed) in [(5000, 3), (40_000, 4)] {
            let bounds = scattered(n, seed);
            let binary = sah::build(&bounds, &[], &BuildOptions::default());
            let wide = WideBvh::<8>::collapse(&binary);
            wide.validate(&bounds).unwrap();
            let lanes: usize = wide
                .nodes()
                .iter()
                .map(|node| node.count.iter().filter(|&&c| c != EMPTY_LANE).count())
                .sum();
            let per_node = lanes as f64 / wide.nodes().len() as f64;
            assert!(per_node > 6.0, "{n} boxes: {per_node} lanes per node");
        }
    }
}
