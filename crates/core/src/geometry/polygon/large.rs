//! Large simple polygons against an exact oracle: a proper triangulation of a simple polygon
//! uses every boundary edge once in its direction and every diagonal once each way, winds
//! every triangle with the polygon, and its areas (f64 shoelace) sum to the polygon's.

use std::collections::HashMap;
use std::time::Instant;

use super::{Triangulation, triangulate_polygon};
use crate::math::Vec3;

/// Twice the signed area of the xy projection, in f64 (exact enough for the tolerance below).
fn area2(a: Vec3, b: Vec3, c: Vec3) -> f64 {
    let (a, b, c) = (a.as_dvec3(), b.as_dvec3(), c.as_dvec3());
    (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)
}

/// Panics unless `tris` is a triangulation of the counter-clockwise simple polygon `p`
/// (allowing dropped zero-area triangles only where `p` has straight vertices).
fn assert_triangulates(p: &[Vec3], tris: &[[usize; 3]], name: &str) {
    let n = p.len();
    let shoelace: f64 = (0..n)
        .map(|i| area2(Vec3::ZERO, p[i], p[(i + 1) % n]))
        .sum();
    let mut sum = 0.0;
    let mut edges: HashMap<(usize, usize), i32> = HashMap::new();
    for &[a, b, c] in tris {
        let t = area2(p[a], p[b], p[c]);
        assert!(
            t > 0.0,
            "{name}: triangle {a} {b} {c} does not wind with the polygon"
        );
        sum += t;
        for (u, v) in [(a, b), (b, c), (c, a)] {
            *edges.entry((u, v)).or_default() += 1;
        }
    }
    assert!(
        (sum - shoelace).abs() <= 1e-9 * shoelace.abs(),
        "{name}: triangles cover {sum}, the polygon {shoelace}"
    );
    // Each boundary edge once forwards; each diagonal once in each direction: no overlap, no
    // gap, no triangle outside the polygon.
    for (&(u, v), &k) in &edges {
        let boundary = v == (u + 1) % n;
        let back = edges.get(&(v, u)).copied().unwrap_or(0);
        assert!(
            k == 1 && (boundary || back == 1),
            "{name}: edge {u}->{v} used {k} times, {back} backwards"
        );
    }
}

fn ears(t: Triangulation, name: &str) -> Vec<[usize; 3]> {
    match t {
        Triangulation::Ears(t) => t,
        other => panic!(
            "{name}: not ear-clipped: {:?}",
            std::mem::discriminant(&other)
        ),
    }
}

/// Star-shaped about the origin with `n` vertices at increasing angles and radii from `r`:
/// simple by construction.
fn star(n: usize, r: impl Fn(usize) -> f64) -> Vec<Vec3> {
    (0..n)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / n as f64;
            Vec3::new((r(k) * a.cos()) as f32, (r(k) * a.sin()) as f32, 0.0)
        })
        .collect()
}

#[test]
fn large_simple_polygons_are_ear_clipped_exactly_and_fast() {
    let mut seed = 0x5eed_u64;
    let mut rand = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut polys = vec![
        (
            "star 2000",
            star(2000, |k| if k % 2 == 0 { 1.0 } else { 0.6 }),
        ),
        ("convex 5000", star(5000, |_| 1.0)),
    ];
    for i in 0..4 {
        let n = [300, 1000, 3000, 5000][i];
        let radii: Vec<f64> = (0..n).map(|_| 0.2 + rand()).collect();
        polys.push(("random star", star(n, |k| radii[k])));
    }
    for (name, p) in &polys {
        let start = Instant::now();
        let tris = ears(triangulate_polygon(p), name);
        let took = start.elapsed();
        assert_eq!(tris.len(), p.len() - 2, "{name}");
        assert_triangulates(p, &tris, name);
        // Generous for a loaded machine: typically a few milliseconds.
        assert!(took.as_secs_f32() < 0.5, "{name}: {took:?}");
    }
    // A convex 5000-gon written with 4 decimals, as exporters do: runs of exactly collinear
    // vertices and slightly reflex ones, no longer fan-shaped, still simple. It used to be
    // fanned with a warning above 4096 vertices.
    let rounded: Vec<Vec3> = star(5000, |_| 1.0)
        .into_iter()
        .map(|v| (v * 1e4).round() / 1e4)
        .collect();
    let tris = ears(triangulate_polygon(&rounded), "rounded convex 5000");
    let n = rounded.len();
    let shoelace: f64 = (0..n)
        .map(|i| area2(Vec3::ZERO, rounded[i], rounded[(i + 1) % n]))
        .sum();
    let sum: f64 = tris
        .iter()
        .map(|&[a, b, c]| area2(rounded[a], rounded[b], rounded[c]))
        .sum();
    assert!(
        tris.iter()
            .all(|&[a, b, c]| area2(rounded[a], rounded[b], rounded[c]) > 0.0)
    );
    assert!(
        (sum - shoelace).abs() <= 1e-9 * shoelace,
        "{sum} vs {shoelace}"
    );
}
