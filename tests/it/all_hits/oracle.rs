//! An exact inside/outside oracle for closed triangle meshes, written independently of lumis's
//! tests: a point on the ray is given by a rational `t`, every coordinate (all dyadic) is
//! scaled to a big integer, and the point is classified by counting where a ray from it in a
//! generic integer direction crosses the triangles, with exact integer orientation tests.
//! A direction that meets an edge or a vertex is replaced by the next; a point on a triangle
//! is `Surface`.

use lumis_core::math::Vec3;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

/// Where a point lies with respect to a closed mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Inside,
    Outside,
    Surface,
}

/// The exact rational value of an `f32`.
pub fn q(x: f32) -> BigRational {
    BigRational::from_float(x).expect("finite")
}

type V = [BigInt; 3];

fn sub(a: &V, b: &V) -> V {
    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
}

fn cross(a: &V, b: &V) -> V {
    [
        &a[1] * &b[2] - &a[2] * &b[1],
        &a[2] * &b[0] - &a[0] * &b[2],
        &a[0] * &b[1] - &a[1] * &b[0],
    ]
}

fn dot(a: &V, b: &V) -> BigInt {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}

fn sign(x: &BigInt) -> i32 {
    if x.is_positive() {
        1
    } else if x.is_negative() {
        -1
    } else {
        0
    }
}

/// Directions with every component positive (so triangles wholly below the point on an axis
/// can be skipped) and no small-integer relation to the test meshes.
const DIRECTIONS: [[i64; 3]; 4] = [
    [1_000_003, 7_919, 104_729],
    [65_537, 1_000_033, 3_571],
    [7_727, 30_011, 1_000_037],
    [999_983, 524_309, 611_953],
];

/// Classifies the point `o + t d` against the closed mesh `tris`.
pub fn classify(o: Vec3, d: Vec3, t: &BigRational, tris: &[[Vec3; 3]]) -> Side {
    let p: [BigRational; 3] = std::array::from_fn(|i| q(o[i]) + t * q(d[i]));
    // One power-of-two scale turns every coordinate into an integer.
    let corners: Vec<BigRational> = tris
        .iter()
        .flatten()
        .flat_map(|v| v.to_array().map(q))
        .collect();
    let scale = p
        .iter()
        .chain(&corners)
        .map(|x| x.denom().clone())
        .fold(BigInt::one(), |a, b| a.max(b));
    let int = |x: &BigRational| -> BigInt {
        let s = x * BigRational::from_integer(scale.clone());
        assert!(s.is_integer(), "dyadic coordinates");
        s.to_integer()
    };
    let p: V = std::array::from_fn(|i| int(&p[i]));
    let tris: Vec<[V; 3]> = tris
        .iter()
        .map(|t| t.map(|v| std::array::from_fn(|i| int(&q(v[i])))))
        .collect();
    // On a triangle: coplanar and inside its closure.
    for [a, b, c] in &tris {
        let n = cross(&sub(b, a), &sub(c, a));
        if !dot(&n, &sub(&p, a)).is_zero() || n.iter().all(Zero::is_zero) {
            continue;
        }
        let inside = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|(u, w)| sign(&dot(&n, &cross(&sub(w, u), &sub(&p, u)))) >= 0);
        if inside {
            return Side::Surface;
        }
    }
    'directions: for r in DIRECTIONS {
        let r: V = r.map(BigInt::from);
        let mut count = 0;
        for [a, b, c] in &tris {
            // Every coordinate along the ray grows: a triangle below the point on some axis
            // cannot be reached.
            if (0..3).any(|i| a[i] < p[i] && b[i] < p[i] && c[i] < p[i]) {
                continue;
            }
            let (pa, pb, pc) = (sub(a, &p), sub(b, &p), sub(c, &p));
            let s = [
                sign(&dot(&cross(&pa, &pb), &r)),
                sign(&dot(&cross(&pb, &pc), &r)),
                sign(&dot(&cross(&pc, &pa), &r)),
            ];
            let (pos, neg) = (s.iter().any(|&x| x > 0), s.iter().any(|&x| x < 0));
            if pos && neg {
                continue; // the line misses the triangle
            }
            let n = cross(&sub(b, a), &sub(c, a));
            let along = sign(&dot(&n, &pa)) * sign(&dot(&n, &r));
            if s.contains(&0) {
                // The line meets the triangle's boundary (or lies in its plane): in front of
                // the point that is ambiguous, so take another direction.
                if along >= 0 {
                    continue 'directions;
                }
                continue;
            }
            if along > 0 {
                count += 1;
            }
        }
        return if count % 2 == 1 {
            Side::Inside
        } else {
            Side::Outside
        };
    }
    panic!("every direction met an edge");
}
