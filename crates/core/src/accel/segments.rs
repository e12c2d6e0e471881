//! The paper's "scale lights": the ray is marched in segments `[t0, t1]` whose length starts at
//! `init` and doubles up to `max`, then one unbounded pass; each segment visits only nodes whose
//! box the ray crosses inside it, and only leaves not searched by an earlier segment.
//!
//! Two defects of the original are fixed here:
//! - The original marks searched nodes with flags inside the shared tree (a data race between
//!   threads). Here nothing is stored at all: a leaf was searched by an earlier segment exactly
//!   when the ray enters its box at or before the (conservatively widened) current `t0` — its
//!   entry distance is computed the same way every time, so the test is exact — and the per-ray
//!   state is just `t0`.
//! - The original returns the first hit found, which may lie in a later segment than a nearer
//!   hit in a leaf not searched yet. Here a hit is accepted only once `t <= t1` of the segment
//!   just finished; a farther one is kept as a candidate (and culls by its distance) meanwhile.

use super::bvh::{Bvh, CullBound, MAX_DEPTH, Node};
use super::{Closest, Hit, TraversalStats};
use crate::geometry::PrimHit;
use crate::math::Ray;
use crate::math::slab::{Slab, with_slab};

/// The paper's segment cap ("the maximum segment length is set as 40000"): the `max` of its
/// Table I configurations and the default of `--segment-max`.
pub const PAPER_SEGMENT_MAX: f32 = 40_000.0;

/// Segment lengths of the scale-lights traversal, in world units along the ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentParams {
    /// Length of the first segment (> 0).
    pub init: f32,
    /// Segments double while no longer than this; then one unbounded pass follows.
    pub max: f32,
}

/// The segment after `[_, t0]`: its end in ray parameter units, or infinity for the last pass.
struct Segments {
    t0: f32,
    len: f32,
    max: f32,
    dir_len: f64,
    index: u32,
}

impl Segments {
    fn new(ray: &Ray, p: &SegmentParams) -> Self {
        Self {
            // From -inf no segment would end anywhere but -inf, so none would search anything
            // before the last, unbounded one, which then skips every leaf entered "before its
            // start" (an entry below -f32::MAX rounds to -inf) as already searched.
            t0: ray.t_min.max(-f32::MAX),
            len: p.init,
            max: p.max,
            // In f64: squares of subnormal or huge components under/overflow in f32.
            dir_len: ray.dir.as_dvec3().length(),
            index: 0,
        }
    }

    /// End of the current segment.
    fn t1(&self) -> f32 {
        if self.len <= self.max {
            self.t0 + (self.len as f64 / self.dir_len) as f32
        } else {
            f32::INFINITY
        }
    }

    fn advance(&mut self) {
        self.t0 = self.t1();
        self.len *= 2.0;
        self.index += 1;
    }
}

impl Bvh {
    /// Nearest hit by segment marching; the same answer as [`Bvh::intersect`].
    pub fn intersect_segments<F>(
        &self,
        ray: &Ray,
        p: &SegmentParams,
        stats: &mut TraversalStats,
        test: F,
    ) -> Option<Hit>
    where
        F: FnMut(u32, &Ray) -> Option<PrimHit>,
    {
        self.march(ray, p, stats, test, false)
    }

    /// Any hit by segment marching: nearer segments first, stopping at the first blocker.
    pub fn occluded_segments<F>(
        &self,
        ray: &Ray,
        p: &SegmentParams,
        stats: &mut TraversalStats,
        mut test: F,
    ) -> bool
    where
        F: FnMut(u32, &Ray) -> bool,
    {
        let mut blocked = false;
        self.walk(ray, p, stats, false, &mut |prim, closest| {
            blocked = test(prim, &closest.ray);
            blocked
        });
        blocked
    }

    /// Segment marching with the ORIGINAL's acceptance rule: the best hit of the first segment
    /// that finds any, even when a nearer hit lies in a later segment's leaf. Wrong answers by
    /// design; it exists only so `lumis-lab paper` can measure what that shortcut saved.
    #[cfg(feature = "paper-original-rule")]
    pub fn intersect_segments_original_rule<F>(
        &self,
        ray: &Ray,
        p: &SegmentParams,
        stats: &mut TraversalStats,
        test: F,
    ) -> Option<Hit>
    where
        F: FnMut(u32, &Ray) -> Option<PrimHit>,
    {
        self.march(ray, p, stats, test, true)
    }

    /// The closest-hit traversal; `accept_any` selects the original's rule of returning the
    /// best hit of the first segment that found any (for the test that shows it wrong).
    fn march<F>(
        &self,
        ray: &Ray,
        p: &SegmentParams,
        stats: &mut TraversalStats,
        mut test: F,
        accept_any: bool,
    ) -> Option<Hit>
    where
        F: FnMut(u32, &Ray) -> Option<PrimHit>,
    {
        self.walk(ray, p, stats, accept_any, &mut |prim, closest| {
            if let Some(h) = test(prim, &closest.ray) {
                closest.offer(prim, h);
            }
            false
        })
    }

    /// Marches the segments, calling `visit(prim, closest)` for each primitive of each newly
    /// searched leaf; `visit` returns true to stop at once. Returns the accepted hit.
    fn walk(
        &self,
        ray: &Ray,
        p: &SegmentParams,
        stats: &mut TraversalStats,
        accept_any: bool,
        visit: &mut dyn FnMut(u32, &mut Closest) -> bool,
    ) -> Option<Hit> {
        with_slab!(ray, |slab| self
            .walk_with(slab, ray, p, stats, accept_any, visit))
    }

    fn walk_with<S: Slab>(
        &self,
        slab: S,
        ray: &Ray,
        p: &SegmentParams,
        stats: &mut TraversalStats,
        accept_any: bool,
        visit: &mut dyn FnMut(u32, &mut Closest) -> bool,
    ) -> Option<Hit> {
        if self.nodes().is_empty() {
            return None;
        }
        let mut closest = Closest::new(ray);
        let mut seg = Segments::new(ray, p);
        let nodes = self.nodes();
        // Boxes are tested against widened bounds (see `CullBound`): a primitive's computed `t`
        // may round just outside its own box's computed interval. Widening is monotonic, so the
        // per-segment ranges `(widen(t0), widen(t1)]` still partition the leaves exactly.
        let cull = CullBound::new(ray, &nodes[0].bounds);
        let t_min = cull.lower(ray.t_min);
        let mut stack = [0u32; MAX_DEPTH + 1];
        loop {
            let t1 = seg.t1();
            let searched_up_to = cull.widen(seg.t0);
            stats.segments += 1;
            stack[0] = 0;
            let mut sp = 1;
            while sp > 0 {
                sp -= 1;
                let node: &Node = &nodes[stack[sp] as usize];
                stats.nodes_visited += 1;
                let upper = cull.widen(t1.min(closest.ray.t_max));
                let Some((near, far)) = slab.range(&node.bounds, t_min, upper) else {
                    continue;
                };
                // Entirely before this segment: every leaf below was searched already.
                if seg.index > 0 && far <= searched_up_to {
                    continue;
                }
                if node.is_leaf() {
                    // Entered within an earlier segment's range: that segment searched this leaf.
                    if seg.index > 0 && near <= searched_up_to {
                        continue;
                    }
                    for &prim in self.leaf_prims(node) {
                        stats.prim_tests += 1;
                        if visit(prim, &mut closest) {
                            return closest.best;
                        }
                    }
                } else {
                    stack[sp] = node.first + 1;
                    stack[sp + 1] = node.first;
                    sp += 2;
                }
            }
            match closest.best {
                Some(b) if b.hit.t <= t1 || accept_any => return Some(b),
                _ if t1 >= closest.ray.t_max => return closest.best,
                _ => seg.advance(),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::{BuildOptions, sah};
    use crate::geometry::{Geometry, Mesh, Sphere, WatertightRay};
    use crate::math::Vec3;

    /// A long slanted triangle whose box starts right at the ray origin but which the ray meets
    /// only at z = 25.4, and a small sphere at z = 10 whose box lies in the second segment.
    fn counter_example() -> Geometry {
        let mut g = Geometry::new();
        let tri = vec![
            Vec3::new(-1.0, -1.0, 0.5),
            Vec3::new(1.0, -1.0, 0.5),
            Vec3::new(0.0, 3.0, 100.0),
        ];
        let mesh = Mesh::new(tri, None, None, vec![[0, 1, 2]]).unwrap();
        g.add_mesh(mesh);
        g.add_sphere(Sphere {
            center: Vec3::new(0.0, 0.0, 10.0),
            radius: 1.0,
        });
        g
    }

    #[test]
    fn original_first_found_rule_is_wrong_and_ours_is_right() {
        let g = counter_example();
        let bvh = sah::build(
            &g.prim_bounds(),
            &[],
            &BuildOptions {
                max_leaf_size: 1,
                ..Default::default()
            },
        );
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        let wr = WatertightRay::new(ray.dir);
        let test = |p: u32, r: &Ray| g.intersect(p, r, &wr);
        let params = SegmentParams {
            init: 2.0,
            max: 40000.0,
        };
        let reference = bvh
            .intersect(&ray, &mut TraversalStats::default(), test)
            .unwrap();
        assert_eq!((reference.prim, reference.hit.t), (1, 9.0));
        let ours = bvh
            .intersect_segments(&ray, &params, &mut TraversalStats::default(), test)
            .unwrap();
        assert_eq!(ours, reference);
        let original = bvh
            .march(&ray, &params, &mut TraversalStats::default(), test, true)
            .unwrap();
        assert_eq!(
            original.prim, 0,
            "the original rule returns the farther triangle"
        );
        assert!(
            original.hit.t > 25.0,
            "the farther hit is at z = 25.4, not {}",
            original.hit.t
        );
    }

    #[test]
    fn segments_from_minus_infinity_still_search_every_leaf() {
        // t_min = -inf and a direction of ~5e-39: the leaf is entered at -3.8e38 (below
        // -f32::MAX once rounded) and hit at t = 1. Marching from -inf, every segment ended at
        // -inf and the last one skipped the leaf as searched (found by the query fuzz target).
        let mut g = Geometry::new();
        for c in [
            [
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(0.0, 0.0, 2.0),
                Vec3::ZERO,
            ],
            [
                Vec3::new(0.0, 0.0, 2.0),
                Vec3::ZERO,
                Vec3::new(0.0, -2.0, 0.0),
            ],
        ] {
            g.add_mesh(Mesh::new(c.to_vec(), None, None, vec![[0, 1, 2]]).unwrap());
        }
        let (x, z) = (f32::from_bits(0x0039_0400), f32::from_bits(0x0004_0000));
        let ray = Ray {
            origin: Vec3::new(x, -0.5, 0.5),
            dir: Vec3::new(-x, 0.0, -z),
            t_min: f32::NEG_INFINITY,
            t_max: f32::INFINITY,
        };
        let bvh = sah::build(
            &g.prim_bounds(),
            &[],
            &BuildOptions {
                max_leaf_size: 4,
                ..Default::default()
            },
        );
        let wr = WatertightRay::new(ray.dir);
        let test = |p: u32, r: &Ray| g.intersect(p, r, &wr);
        let params = SegmentParams {
            init: 0.05,
            max: 1.6,
        };
        let got = bvh.intersect_segments(&ray, &params, &mut TraversalStats::default(), test);
        assert_eq!(got.map(|h| (h.prim, h.hit.t)), Some((1, 1.0)));
    }

    #[test]
    fn each_leaf_is_searched_at_most_once_per_ray() {
        let g = counter_example();
        let bvh = sah::build(
            &g.prim_bounds(),
            &[],
            &BuildOptions {
                max_leaf_size: 1,
                ..Default::default()
            },
        );
        let ray = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
        let wr = WatertightRay::new(ray.dir);
        let mut stats = TraversalStats::default();
        let params = SegmentParams {
            init: 0.5,
            max: 40000.0,
        };
        bvh.intersect_segments(&ray, &params, &mut stats, |p, r| g.intersect(p, r, &wr));
        assert!(stats.prim_tests <= 2, "{stats:?}");
        assert!(stats.segments > 3);
    }
}
