//! The ear clipper behind [`super::triangulate_polygon`], for polygons that are not fan-shaped.

use std::cmp::Ordering::{Greater, Less};

use super::{Triangulation, fan, zero_area};
use crate::geometry::exact::orient2d;
use crate::math::Vec3;

/// How often stale ear flags may be recomputed before a polygon is declared not simple (see
/// [`clip_ears`]); bounded so the total stays `O(n^2)`.
const MAX_RESCANS: usize = 4;

/// The remaining polygon of an ear clipper: a doubly linked cycle over the input vertices.
struct Ring<'a> {
    points: &'a [Vec3],
    p: &'a [[f64; 2]],
    prev: Vec<usize>,
    next: Vec<usize>,
    /// Strictly counter-clockwise turn at the vertex, with its current neighbours.
    convex: Vec<bool>,
    /// Whether the vertex may be clipped now (see [`Ring::is_ear`]).
    ear: Vec<bool>,
    /// Clipped already.
    removed: Vec<bool>,
    /// Every vertex that may block an ear (not convex), plus entries gone stale (removed or
    /// convex since), skipped when read and swept out now and then: ear tests cost the
    /// number of reflex vertices, not of all vertices.
    blockers: Vec<usize>,
    /// Whether the vertex is in `blockers`.
    listed: Vec<bool>,
}

impl Ring<'_> {
    fn triangle(&self, b: usize) -> [usize; 3] {
        [self.prev[b], b, self.next[b]]
    }

    fn update_convex(&mut self, b: usize) {
        let [a, _, c] = self.triangle(b);
        self.convex[b] = orient2d(self.p[a], self.p[b], self.p[c]) == Greater;
        if !self.convex[b] && !self.listed[b] {
            self.blockers.push(b);
            self.listed[b] = true;
        }
    }

    /// Drops the stale entries of `blockers`.
    fn sweep(&mut self) {
        let (removed, convex, listed) = (&self.removed, &self.convex, &mut self.listed);
        self.blockers.retain(|&v| {
            let keep = !removed[v] && !convex[v];
            listed[v] = keep;
            keep
        });
    }

    /// A vertex may be clipped when its triangle has exactly zero area (clipping it then
    /// removes no area, so no triangle is emitted), or when it turns strictly left and no
    /// vertex that does not lies inside or on its triangle. Only such (reflex or straight)
    /// vertices need testing: in a simple polygon, a triangle that holds any vertex holds a
    /// reflex one. Vertices repeated at a corner's spot (bridges to holes) do not count.
    fn is_ear(&self, b: usize) -> bool {
        let [a, _, c] = self.triangle(b);
        if zero_area(self.points, [a, b, c]) {
            return true;
        }
        if !self.convex[b] {
            return false;
        }
        let (pa, pb, pc) = (self.p[a], self.p[b], self.p[c]);
        // The triangle's bounding box: a cheap exact reject before the orientation tests.
        let lo = [0, 1].map(|k| pa[k].min(pb[k]).min(pc[k]));
        let hi = [0, 1].map(|k| pa[k].max(pb[k]).max(pc[k]));
        for &v in &self.blockers {
            let q = self.p[v];
            if (0..2).all(|k| lo[k] <= q[k] && q[k] <= hi[k])
                && !self.convex[v]
                && !self.removed[v]
                && v != a
                && v != b
                && v != c
                && q != pa
                && q != pb
                && q != pc
                && orient2d(pa, pb, q) != Less
                && orient2d(pb, pc, q) != Less
                && orient2d(pc, pa, q) != Less
            {
                return false;
            }
        }
        true
    }

    /// The remaining vertices in order, starting at `start`.
    fn walk(&self, start: usize) -> Vec<usize> {
        let mut out = vec![start];
        let mut v = self.next[start];
        while v != start {
            out.push(v);
            v = self.next[v];
        }
        out
    }
}

/// Ear clipping of a counter-clockwise 2-D polygon (`p`, the projection of `points`), in
/// `O(n^2)`: each vertex's ear flag is computed once and then only for the two neighbours of
/// a clipped vertex, the only ones whose triangle changes (clipping a convex ear tip cannot
/// unblock anyone else, by the reflex-vertex argument of [`Ring::is_ear`]). Clipping a
/// straight vertex can, so when no ear is flagged the flags are recomputed, at most
/// [`MAX_RESCANS`] times, before the rest is fanned as not simple.
pub(super) fn clip_ears(points: &[Vec3], p: &[[f64; 2]]) -> Triangulation {
    let n = p.len();
    let mut ring = Ring {
        points,
        p,
        prev: (0..n).map(|i| (i + n - 1) % n).collect(),
        next: (0..n).map(|i| (i + 1) % n).collect(),
        convex: vec![false; n],
        ear: vec![false; n],
        removed: vec![false; n],
        blockers: Vec::new(),
        listed: vec![false; n],
    };
    (0..n).for_each(|b| ring.update_convex(b));
    ring.ear = (0..n).map(|b| ring.is_ear(b)).collect();
    let mut tris = Vec::with_capacity(n - 2);
    let (mut left, mut cursor, mut rescans, mut stale) = (n, 0, 0, false);
    while left > 3 {
        // Search from the last clip's neighbour, so ears come out in order around the polygon.
        let (mut b, mut found) = (cursor, false);
        for _ in 0..left {
            if ring.ear[b] {
                found = true;
                break;
            }
            b = ring.next[b];
        }
        if !found {
            if stale && rescans < MAX_RESCANS {
                (rescans, stale) = (rescans + 1, false);
                for v in ring.walk(cursor) {
                    ring.ear[v] = ring.is_ear(v);
                }
                continue;
            }
            // Not a simple polygon: no ear exists. Fan the rest rather than fail.
            tris.extend(fan(points, &ring.walk(cursor)));
            return Triangulation::Fan(tris);
        }
        let [a, _, c] = ring.triangle(b);
        if !zero_area(points, [a, b, c]) {
            tris.push([a, b, c]);
        }
        stale |= !ring.convex[b];
        (ring.next[a], ring.prev[c]) = (c, a);
        ring.removed[b] = true;
        left -= 1;
        if left.is_power_of_two() {
            ring.sweep();
        }
        for v in [a, c] {
            ring.update_convex(v);
        }
        for v in [a, c] {
            ring.ear[v] = ring.is_ear(v);
        }
        cursor = a;
    }
    let last = ring.triangle(ring.next[cursor]);
    if !zero_area(points, last) {
        tris.push(last);
    }
    if tris.is_empty() {
        Triangulation::Degenerate
    } else {
        Triangulation::Ears(tris)
    }
}
