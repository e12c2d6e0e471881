//! Triangulation of polygons by ear clipping, for OBJ n-gons.
//!
//! **The rule: a triangle is dropped only when its area is zero in exact arithmetic on its
//! `f32` corners** ([`triangle_area_is_zero`]); every triangle with any real area, however thin
//! or far from the origin, is kept. Earlier versions compared an `f32` Newell normal with the
//! polygon's extent and clipped "collinear" vertices within an `f32` tolerance; far from the
//! origin both cancel, and real slivers were dropped, leaving holes in closed meshes.
//!
//! So nothing here has a tolerance. The polygon is projected along the dominant axis of its
//! Newell normal (computed in `f64` about its first vertex): the projected coordinates are the
//! `f32` inputs themselves, unrounded, and every turn and containment test is an exact
//! [`orient2d`] on them. The axes are ordered so the projection winds counter-clockwise, hence
//! ears are clipped in that plane, concave polygons come out right and every triangle keeps the
//! polygon's winding (its normal agrees with the Newell normal).

use std::cmp::Ordering::Greater;

mod ears;
#[cfg(test)]
mod large;

use super::exact::{orient2d, triangle_area_is_zero};
use crate::math::Vec3;
use ears::clip_ears;
use glam::DVec3;

/// Above this many vertices a polygon that is not fan-shaped is fanned instead of ear-clipped:
/// ear clipping here costs `O(n r)` exact tests (`r` reflex vertices), and hostile files must
/// not stall the loader. A 5000-gon takes milliseconds; the worst case at this size (half the
/// vertices reflex) about 4e8 cheap box tests, well under a second.
const MAX_EAR_CLIP_VERTICES: usize = 16_384;

/// How a polygon was split into triangles; indices are positions in the input slice.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Triangulation {
    /// A proper triangulation covering exactly the polygon: `n - 2` triangles, fewer only when
    /// some had exactly zero area (collinear or repeated vertices), which covers nothing.
    Ears(Vec<[usize; 3]>),
    /// The polygon is not simple (no ear could be found, e.g. it crosses itself), has no plane
    /// (its vector area is zero), or is too large to ear-clip: what was left is a fan around
    /// its first remaining vertex, without the fan triangles of exactly zero area.
    Fan(Vec<[usize; 3]>),
    /// Fewer than 3 vertices, a non-finite one, or no triangle of nonzero exact area at all
    /// (every vertex collinear or coincident with the others).
    Degenerate,
}

/// Newell's normal of a polygon: twice its vector area, robust to concavity and mild
/// non-planarity; zero for a degenerate polygon. Summed in `f64` about the first vertex, so
/// distance from the origin costs no precision.
pub fn newell_normal(points: &[Vec3]) -> Vec3 {
    newell_f64(points).as_vec3()
}

/// [`newell_normal`] before rounding to `f32`: the sum of `(a - o) x (b - o)` over the edges.
fn newell_f64(points: &[Vec3]) -> DVec3 {
    let Some(o) = points.first().map(|p| p.as_dvec3()) else {
        return DVec3::ZERO;
    };
    let mut n = DVec3::ZERO;
    for (i, a) in points.iter().enumerate() {
        let b = points[(i + 1) % points.len()];
        n += (a.as_dvec3() - o).cross(b.as_dvec3() - o);
    }
    n
}

/// Splits the polygon `points` (in order, either winding) into triangles that wind the same
/// way, dropping only triangles of exactly zero area.
pub fn triangulate_polygon(points: &[Vec3]) -> Triangulation {
    let n = points.len();
    if n < 3 || points.iter().any(|p| !p.is_finite()) {
        return Triangulation::Degenerate;
    }
    if n == 3 {
        return if triangle_area_is_zero(points[0], points[1], points[2]) {
            Triangulation::Degenerate
        } else {
            Triangulation::Ears(vec![[0, 1, 2]])
        };
    }
    let normal = newell_f64(points);
    let k = (0..3)
        .max_by(|&a, &b| normal[a].abs().total_cmp(&normal[b].abs()))
        .unwrap_or(2);
    if normal[k] == 0.0 {
        // No plane to project on (a figure eight whose lobes cancel, or collinear points).
        let all: Vec<usize> = (0..n).collect();
        return fan_or_degenerate(points, &all);
    }
    // Dropping axis k, (k + 1, k + 2) is counter-clockwise seen from +k; swapped for -k.
    let (i, j) = if normal[k] > 0.0 {
        ((k + 1) % 3, (k + 2) % 3)
    } else {
        ((k + 2) % 3, (k + 1) % 3)
    };
    let p2: Vec<[f64; 2]> = points.iter().map(|p| [p[i] as f64, p[j] as f64]).collect();
    if fans_from_first(&p2) {
        return Triangulation::Ears((1..n - 1).map(|i| [0, i, i + 1]).collect());
    }
    if n > MAX_EAR_CLIP_VERTICES {
        let all: Vec<usize> = (0..n).collect();
        return fan_or_degenerate(points, &all);
    }
    clip_ears(points, &p2)
}

/// True when the fan around vertex 0 is a triangulation: every fan triangle turns strictly
/// counter-clockwise and every other vertex lies strictly left of the edge 0 -> 1, so the fan's
/// wedges sweep less than a half turn in order and cannot overlap. Convex polygons (however
/// many vertices) and polygons star-shaped about vertex 0 pass.
fn fans_from_first(p: &[[f64; 2]]) -> bool {
    let n = p.len();
    (1..n - 1).all(|i| orient2d(p[0], p[i], p[i + 1]) == Greater)
        && (3..n).all(|i| orient2d(p[0], p[1], p[i]) == Greater)
}

/// The fan around `idx[0]` over the vertices `idx` (in order), without its triangles of exactly
/// zero area; `Degenerate` when none is left.
fn fan_or_degenerate(points: &[Vec3], idx: &[usize]) -> Triangulation {
    let tris = fan(points, idx);
    if tris.is_empty() {
        Triangulation::Degenerate
    } else {
        Triangulation::Fan(tris)
    }
}

/// The fan triangles of nonzero exact area around `idx[0]`.
pub(super) fn fan(points: &[Vec3], idx: &[usize]) -> Vec<[usize; 3]> {
    (1..idx.len().saturating_sub(1))
        .map(|j| [idx[0], idx[j], idx[j + 1]])
        .filter(|t| !zero_area(points, *t))
        .collect()
}

pub(super) fn zero_area(points: &[Vec3], [a, b, c]: [usize; 3]) -> bool {
    triangle_area_is_zero(points[a], points[b], points[c])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec2;

    fn area(points: &[Vec3], tris: &[[usize; 3]]) -> f32 {
        tris.iter()
            .map(|[a, b, c]| 0.5 * (points[*b] - points[*a]).cross(points[*c] - points[*a]).z)
            .sum()
    }

    fn tris_of(t: Triangulation) -> Vec<[usize; 3]> {
        match t {
            Triangulation::Ears(t) => t,
            other => panic!("expected ears, got {other:?}"),
        }
    }

    /// The L: the 2 x 2 square minus its top-right unit square, counter-clockwise.
    fn l_shape() -> Vec<Vec3> {
        [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]
            .map(|(x, y)| Vec3::new(x, y, 0.0))
            .to_vec()
    }

    #[test]
    fn concave_l_gives_four_triangles_inside_the_l() {
        let p = l_shape();
        let tris = tris_of(triangulate_polygon(&p));
        assert_eq!(tris.len(), 4);
        // Every triangle winds counter-clockwise (positive area) and together they cover 3.
        assert!((area(&p, &tris) - 3.0).abs() < 1e-6);
        // Coverage on a grid of points off every edge and diagonal: once inside the L, never in
        // the notch.
        for i in 0..20 {
            for j in 0..20 {
                let q = Vec2::new(0.037 + 0.1 * i as f32, 0.061 + 0.1 * j as f32);
                let covering = tris
                    .iter()
                    .filter(|t| {
                        let [a, b, c] = t.map(|k| p[k].truncate());
                        (b - a).perp_dot(q - a) > 0.0
                            && (c - b).perp_dot(q - b) > 0.0
                            && (a - c).perp_dot(q - c) > 0.0
                    })
                    .count();
                let in_notch = q.x > 1.0 && q.y > 1.0;
                assert_eq!(covering, usize::from(!in_notch), "at {q}");
            }
        }
    }

    #[test]
    fn clockwise_and_tilted_polygons_keep_their_winding() {
        // The L reversed and rotated out of the xy plane: triangle normals follow the Newell normal.
        let rot = crate::math::Mat4::from_rotation_x(0.7) * crate::math::Mat4::from_rotation_y(0.3);
        let p: Vec<Vec3> = l_shape()
            .into_iter()
            .rev()
            .map(|q| rot.transform_point3(q))
            .collect();
        let w = newell_normal(&p);
        let tris = tris_of(triangulate_polygon(&p));
        assert_eq!(tris.len(), 4);
        let total: f32 = tris
            .iter()
            .map(|[a, b, c]| {
                let n = (p[*b] - p[*a]).cross(p[*c] - p[*a]);
                assert!(n.dot(w) > 0.0);
                0.5 * n.length()
            })
            .sum();
        assert!((total - 3.0).abs() < 1e-5);
    }

    #[test]
    fn degenerate_and_self_intersecting_inputs_do_not_panic() {
        let line: Vec<Vec3> = (0..5).map(|i| Vec3::X * i as f32).collect();
        assert_eq!(triangulate_polygon(&line), Triangulation::Degenerate);
        assert_eq!(
            triangulate_polygon(&[Vec3::ZERO; 4]),
            Triangulation::Degenerate
        );
        assert_eq!(triangulate_polygon(&line[..2]), Triangulation::Degenerate);
        let nan = [Vec3::ZERO, Vec3::X, Vec3::NAN, Vec3::Y];
        assert_eq!(triangulate_polygon(&nan), Triangulation::Degenerate);
        // A square with a collinear midpoint on one edge: at most 3 triangles, no sliver.
        let sq =
            [(0., 0.), (1., 0.), (2., 0.), (2., 2.), (0., 2.)].map(|(x, y)| Vec3::new(x, y, 0.));
        let tris = tris_of(triangulate_polygon(&sq));
        assert!((area(&sq, &tris) - 4.0).abs() < 1e-6 && tris.len() <= 3);
        // A bow-tie pentagram crosses itself: any result, but in range and no panic.
        let star: Vec<Vec3> = (0..5)
            .map(|i| {
                let a = i as f32 * 4.0 * std::f32::consts::PI / 5.0;
                Vec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        match triangulate_polygon(&star) {
            Triangulation::Ears(t) | Triangulation::Fan(t) => {
                assert!(t.iter().flatten().all(|&i| i < 5))
            }
            Triangulation::Degenerate => {}
        }
    }

    /// Twice the area of each triangle, in f64 (exact for these small integer-ish inputs).
    fn area64(points: &[Vec3], tris: &[[usize; 3]]) -> f64 {
        tris.iter()
            .map(|&[a, b, c]| {
                let o = points[a].as_dvec3();
                (points[b].as_dvec3() - o)
                    .cross(points[c].as_dvec3() - o)
                    .length()
            })
            .sum()
    }

    #[test]
    fn thin_and_far_triangles_are_kept() {
        let v = Vec3::new;
        // The external report's 1000 x 0.001 sliver, and the same far from the origin.
        let sliver = [v(0., 0., 0.), v(1000., 0., 0.), v(1000., 0.001, 0.)];
        assert_eq!(
            triangulate_polygon(&sliver),
            Triangulation::Ears(vec![[0, 1, 2]])
        );
        let o = v(148376.0, 1235.0, -223423.0);
        let far = [o, o + v(0.05, 0., 0.), o + v(0., 0.05, 0.)];
        assert_eq!(
            triangulate_polygon(&far),
            Triangulation::Ears(vec![[0, 1, 2]])
        );
        // A quad sliver far away: both triangles survive.
        let quad = [
            o,
            o + v(1000., 0., 0.),
            o + v(1000., 0.02, 0.),
            o + v(0., 0.02, 0.),
        ];
        let tris = tris_of(triangulate_polygon(&quad));
        assert_eq!(tris.len(), 2);
    }

    #[test]
    fn only_exactly_zero_area_pieces_are_dropped() {
        // Exactly collinear corners, however long, far or many: nothing to keep.
        let o = Vec3::new(1e7, -2e6, 3e5);
        let line: Vec<Vec3> = (0..6)
            .map(|i| o + Vec3::new(2.0, 4.0, 8.0) * i as f32)
            .collect();
        assert_eq!(triangulate_polygon(&line), Triangulation::Degenerate);
        assert_eq!(triangulate_polygon(&line[..3]), Triangulation::Degenerate);
        // A spike (out and back along one line) glued to a square: only the square's area.
        let sq = [(0., 0.), (1., 0.), (3., 0.), (1., 0.), (1., 1.), (0., 1.)]
            .map(|(x, y)| Vec3::new(x, y, 0.0));
        let tris = tris_of(triangulate_polygon(&sq));
        assert_eq!(area64(&sq, &tris), 2.0);
        assert!(tris.iter().all(|&t| !zero_area(&sq, t)));
    }

    #[test]
    fn large_convex_and_star_polygons_are_triangulated_properly() {
        // A convex 5000-gon: all f32 corners, the fan passes the exact convexity test.
        let n = 5000;
        let ring = |r: f32, k: usize| {
            let a = k as f64 * std::f64::consts::TAU / n as f64;
            Vec3::new(
                (r as f64 * a.cos()) as f32,
                (r as f64 * a.sin()) as f32,
                0.0,
            )
        };
        let convex: Vec<Vec3> = (0..n).map(|k| ring(1.0, k)).collect();
        let tris = tris_of(triangulate_polygon(&convex));
        assert_eq!(tris.len(), n - 2);
        // A star 2000-gon: alternating radii 1 and 0.5 (so not fan-shaped from vertex 0's
        // neighbourhood), needs real ear clipping.
        let m = 2000;
        let star: Vec<Vec3> = (0..m)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / m as f64;
                let r = if k % 2 == 0 { 1.0 } else { 0.5 };
                Vec3::new((r * a.cos()) as f32, (r * a.sin()) as f32, 0.0)
            })
            .collect();
        let shifted: Vec<Vec3> = star.iter().map(|p| *p + Vec3::new(1.0, 0.0, 0.0)).collect();
        for poly in [&star, &shifted] {
            let tris = tris_of(triangulate_polygon(poly));
            assert_eq!(tris.len(), m - 2);
            let signed: f64 = tris
                .iter()
                .map(|&[a, b, c]| {
                    let o = poly[a].as_dvec3();
                    (poly[b].as_dvec3() - o).cross(poly[c].as_dvec3() - o).z
                })
                .sum();
            // Every triangle winds counter-clockwise, so the signed and unsigned sums agree,
            // and they equal the polygon's (Newell) area.
            assert!((signed - area64(poly, &tris)).abs() < 1e-9);
            assert!((signed - newell_f64(poly).z).abs() < 1e-9, "{signed}");
        }
    }

    #[test]
    fn bridged_hole_and_skew_quad_are_ear_clipped() {
        // A 4 x 4 square with a 2 x 2 hole, joined by a bridge walked both ways (repeated
        // vertices): 12 of area, every triangle counter-clockwise.
        let p = [
            (0., 0.),
            (4., 0.),
            (4., 4.),
            (0., 4.),
            (1., 3.),
            (3., 3.),
            (3., 1.),
            (1., 1.),
            (1., 3.),
            (0., 4.),
        ]
        .map(|(x, y)| Vec3::new(x, y, 0.0));
        let tris = tris_of(triangulate_polygon(&p));
        assert!(tris.iter().all(|&t| area(&p, &[t]) > 0.0));
        assert_eq!(area64(&p, &tris), 24.0);
        // Slightly non-planar: both triangles kept, winding with the Newell normal.
        let q = [Vec3::ZERO, Vec3::X, Vec3::new(1., 1., 1e-3), Vec3::Y];
        let tris = tris_of(triangulate_polygon(&q));
        assert_eq!(tris.len(), 2);
        let w = newell_normal(&q);
        assert!(
            tris.iter()
                .all(|&[a, b, c]| (q[b] - q[a]).cross(q[c] - q[a]).dot(w) > 0.0)
        );
    }
}
