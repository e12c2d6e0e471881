//! Triangulation of planar (or nearly planar) polygons by ear clipping, for OBJ n-gons.
//!
//! The polygon is projected onto the plane of its Newell normal, where its winding is
//! counter-clockwise by construction; ears are clipped in that 2-D plane, so concave polygons
//! come out right and every triangle keeps the polygon's winding (its normal agrees with the
//! Newell normal).

use crate::math::{Vec2, Vec3};

/// Above this many vertices a concave polygon is fanned instead of ear-clipped: ear clipping
/// costs up to `O(n^3)`, and hostile files must not stall the loader.
const MAX_EAR_CLIP_VERTICES: usize = 1024;

/// How a polygon was split into triangles; indices are positions in the input slice.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Triangulation {
    /// A proper triangulation: `n - 2` triangles covering exactly the polygon (fewer when
    /// collinear vertices were dropped, which removes only zero-area slivers).
    Ears(Vec<[usize; 3]>),
    /// The polygon is not simple (no ear could be found, e.g. it crosses itself) or too large
    /// to ear-clip: what was left is a fan around its first remaining vertex.
    Fan(Vec<[usize; 3]>),
    /// Fewer than 3 vertices, non-finite, or zero area (collinear or coincident points).
    Degenerate,
}

/// Newell's normal of a polygon: twice its vector area, robust to concavity and mild
/// non-planarity; zero for a degenerate polygon.
pub fn newell_normal(points: &[Vec3]) -> Vec3 {
    let mut n = Vec3::ZERO;
    for (i, a) in points.iter().enumerate() {
        let b = points[(i + 1) % points.len()];
        n += Vec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    n
}

/// Splits the polygon `points` (in order, either winding) into triangles that wind the same way.
pub fn triangulate_polygon(points: &[Vec3]) -> Triangulation {
    let n = points.len();
    if n < 3 || points.iter().any(|p| !p.is_finite()) {
        return Triangulation::Degenerate;
    }
    let normal = newell_normal(points);
    // Origin near the polygon keeps the projected coordinates' rounding error small.
    let origin = points[0];
    let extent2 = points
        .iter()
        .map(|p| (*p - origin).length_squared())
        .fold(0.0, f32::max);
    // The Newell normal's length is twice the area; compare it with the polygon's size squared.
    // Overflow (coordinates near f32::MAX) leaves no usable plane either.
    if !normal.is_finite() || normal.length() <= 1e-6 * extent2 {
        return Triangulation::Degenerate;
    }
    let w = normal.normalize();
    let u = w.any_orthonormal_vector();
    // u x v = w, so the projection is counter-clockwise.
    let v = w.cross(u);
    let p2: Vec<Vec2> = points
        .iter()
        .map(|p| Vec2::new((*p - origin).dot(u), (*p - origin).dot(v)))
        .collect();
    let eps = 1e-7 * extent2;
    let turn = |a: usize, b: usize, c: usize| (p2[b] - p2[a]).perp_dot(p2[c] - p2[b]);
    let convex = (0..n).all(|i| turn((i + n - 1) % n, i, (i + 1) % n) > eps);
    if convex {
        return Triangulation::Ears((1..n - 1).map(|i| [0, i, i + 1]).collect());
    }
    if n > MAX_EAR_CLIP_VERTICES {
        return Triangulation::Fan((1..n - 1).map(|i| [0, i, i + 1]).collect());
    }
    clip_ears(&p2, eps)
}

/// Ear clipping of a counter-clockwise 2-D polygon that is not strictly convex.
fn clip_ears(p2: &[Vec2], eps: f32) -> Triangulation {
    let turn = |a: usize, b: usize, c: usize| (p2[b] - p2[a]).perp_dot(p2[c] - p2[b]);
    let mut left: Vec<usize> = (0..p2.len()).collect();
    let mut tris = Vec::with_capacity(p2.len() - 2);
    // Where the search resumes: just before the last clipped vertex, so ears come out in order.
    let mut k = 0;
    while left.len() > 3 {
        let m = left.len();
        let found = (0..m).map(|j| (k + j) % m).find(|&i| {
            let (a, b, c) = (left[(i + m - 1) % m], left[i], left[(i + 1) % m]);
            let t = turn(a, b, c);
            // A collinear vertex is clipped with no triangle: it adds only a zero-area sliver.
            t.abs() <= eps || (t > eps && is_empty_ear(p2, &left, [a, b, c], eps))
        });
        let Some(i) = found else {
            // Not a simple polygon: no ear exists. Fan the rest rather than fail.
            tris.extend((1..m - 1).map(|j| [left[0], left[j], left[j + 1]]));
            return Triangulation::Fan(tris);
        };
        let (a, b, c) = (left[(i + m - 1) % m], left[i], left[(i + 1) % m]);
        if turn(a, b, c) > eps {
            tris.push([a, b, c]);
        }
        left.remove(i);
        k = (i + left.len() - 1) % left.len();
    }
    if turn(left[0], left[1], left[2]) > eps {
        tris.push([left[0], left[1], left[2]]);
    }
    Triangulation::Ears(tris)
}

/// True when no other remaining vertex lies inside or on the counter-clockwise triangle
/// `abc`. Vertices at the same spot as a corner (duplicated points) do not count.
fn is_empty_ear(p2: &[Vec2], left: &[usize], [a, b, c]: [usize; 3], eps: f32) -> bool {
    let (pa, pb, pc) = (p2[a], p2[b], p2[c]);
    left.iter().all(|&j| {
        let q = p2[j];
        if j == a || j == b || j == c || q == pa || q == pb || q == pc {
            return true;
        }
        let inside = (pb - pa).perp_dot(q - pa) >= -eps
            && (pc - pb).perp_dot(q - pb) >= -eps
            && (pa - pc).perp_dot(q - pc) >= -eps;
        !inside
    })
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
