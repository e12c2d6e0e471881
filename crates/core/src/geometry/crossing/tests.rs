use super::*;
use crate::geometry::Mesh;

/// A splitmix64 stream of small integers in `-r..=r` (exact in every arithmetic used here).
fn ints(seed: u64, r: i64) -> impl FnMut() -> i64 {
    let mut s = seed;
    move || {
        s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) % (2 * r as u64 + 1)) as i64 - r
    }
}

fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

fn axes(d: Vec3) -> [usize; 3] {
    let wr = WatertightRay::new(d);
    [wr.kx, wr.ky, wr.kz]
}

#[test]
fn perturbed_signs_are_the_exact_derivatives_and_flip_with_the_edge() {
    let mut next = ints(3, 6);
    let mut vec = || [next(), next(), next()];
    for _ in 0..5000 {
        let (p, q, d) = (vec(), vec(), vec());
        if d == [0, 0, 0] {
            continue;
        }
        let f = |a: [i64; 3]| v(a[0] as f32, a[1] as f32, a[2] as f32);
        let k = axes(f(d));
        let [kx, ky, kz] = k;
        let e = [0, 1, 2].map(|i| q[i] - p[i]);
        // Integers: the derivatives times d[kz] are exact in i64.
        let first = (e[ky] * d[kz] - d[ky] * e[kz]) * d[kz].signum();
        let second = -(e[kx] * d[kz] - d[kx] * e[kz]) * d[kz].signum();
        let want = if first != 0 {
            first.cmp(&0)
        } else {
            second.cmp(&0)
        };
        let got = perturbed_sign(f(d), f(p), f(q), k);
        assert_eq!(got, want, "p {p:?} q {q:?} d {d:?}");
        assert_eq!(perturbed_sign(f(d), f(q), f(p), k), got.reverse());
        // Equal exactly when the edge is parallel to the ray (or has no length).
        let cross = [
            e[1] * d[2] - e[2] * d[1],
            e[2] * d[0] - e[0] * d[2],
            e[0] * d[1] - e[1] * d[0],
        ];
        assert_eq!(got.is_eq(), cross == [0, 0, 0]);
    }
}

#[test]
fn differences_that_are_not_exact_in_f64_keep_their_sign() {
    // (2^100 + 1 - 2^100) * 1 - 0: the rounded difference of the f64s would be 1 exactly here,
    // but a 2^-60 beside 2^60 is lost by f64 subtraction and must not be.
    let big = 2f32.powi(60);
    let tiny = 2f32.powi(-60);
    assert_eq!(
        cross_of_difference(big, big, 1.0, tiny, 0.0, 1.0),
        Ordering::Greater
    );
    assert_eq!(
        cross_of_difference(-tiny, big, 1.0, 0.0, big, 1.0),
        Ordering::Greater
    );
    assert_eq!(
        cross_of_difference(tiny, big, 1.0, 0.0, big, 1.0),
        Ordering::Less
    );
    assert_eq!(
        cross_of_difference(3.0, 5.0, 3.0, 1.0, 4.0, 2.0),
        Ordering::Equal
    );
}

/// The touches of a ray with every triangle of `tris` (a mesh with shared vertices).
fn touches(positions: Vec<Vec3>, indices: Vec<[u32; 3]>, ray: Ray) -> Vec<Contact> {
    let mut g = Geometry::new();
    g.add_mesh(Mesh::new(positions, None, None, indices).unwrap());
    let wr = WatertightRay::new(ray.dir);
    let mut out = Vec::new();
    for p in 0..g.prims().len() as u32 {
        g.contacts(p, &ray, &wr, Precision::Watertight, &mut out);
    }
    out
}

fn claims(c: &[Contact]) -> usize {
    c.iter()
        .filter(|c| matches!(c.touch, Touch::Boundary { claims: true, .. }))
        .count()
}

#[test]
fn a_shared_edge_is_claimed_once_when_crossed_and_zero_or_two_times_when_grazed() {
    // A flat quad split along its diagonal: straight through the diagonal is a crossing.
    let quad = vec![v(0., 0., 0.), v(2., 0., 0.), v(2., 2., 0.), v(0., 2., 0.)];
    let idx = vec![[0, 1, 2], [0, 2, 3]];
    for d in [
        v(0., 0., -1.),
        v(1., 2., -3.),
        v(-3., 1., -1.),
        v(0., 0., 1.),
    ] {
        let c = touches(quad.clone(), idx.clone(), Ray::new(v(1., 1., 0.) - d, d));
        assert_eq!(c.len(), 2, "{d}");
        assert_eq!(claims(&c), 1, "{d}");
        assert!(matches!(
            c[0].touch,
            Touch::Boundary {
                seam: Seam::Edge { .. },
                ..
            }
        ));
        assert_eq!(c[0].touch_seam(), c[1].touch_seam());
    }
    // A roof folded along the same diagonal: a ray along the fold's normal plane touching only
    // the ridge grazes it.
    let roof = vec![v(0., 0., 0.), v(2., 0., 1.), v(2., 2., 0.), v(0., 2., 1.)];
    // The ridge runs from (0,0,0) to (2,2,0); (2,0,1) and (0,2,1) lie above it, so a
    // horizontal ray across the ridge, below the wings, only touches the ridge.
    for d in [v(1., -1., 0.), v(-1., 1., 0.), v(1., -1., -1e-3)] {
        let c = touches(
            roof.clone(),
            idx.clone(),
            Ray::new(v(1., 1., 0.) - d * 4.0, d),
        );
        assert_eq!(c.len(), 2, "{d}");
        assert_ne!(claims(&c), 1, "{d}");
    }
}

impl Contact {
    fn touch_seam(&self) -> Option<Seam> {
        match self.touch {
            Touch::Boundary { seam, .. } => Some(seam),
            _ => None,
        }
    }
}

#[test]
fn a_vertex_of_a_fan_is_claimed_once_when_crossed() {
    // Six triangles around the centre of a flat hexagon-like fan; straight through the centre.
    let mut p = vec![v(0., 0., 0.)];
    let ring = [(4, 0), (2, 3), (-2, 3), (-4, 0), (-2, -3), (2, -3)];
    p.extend(ring.iter().map(|&(x, y)| v(x as f32, y as f32, 0.)));
    let idx: Vec<[u32; 3]> = (0..6).map(|i| [0, 1 + i, 1 + (i + 1) % 6]).collect();
    let mut next = ints(11, 5);
    for _ in 0..300 {
        let d = v(next() as f32, next() as f32, (next().abs() + 1) as f32);
        let c = touches(p.clone(), idx.clone(), Ray::new(-d, d));
        assert!(c.iter().all(|c| matches!(
            c.touch,
            Touch::Boundary {
                seam: Seam::Vertex { .. } | Seam::Edge { .. },
                ..
            }
        )));
        assert_eq!(claims(&c), 1, "{d}: {c:?}");
    }
}

#[test]
fn spheres_give_two_crossings_or_one_graze() {
    let mut g = Geometry::new();
    g.add_sphere(Sphere {
        center: Vec3::ZERO,
        radius: 1.0,
    });
    let run = |ray: Ray| {
        let mut out = Vec::new();
        g.contacts(
            0,
            &ray,
            &WatertightRay::new(ray.dir),
            Precision::Watertight,
            &mut out,
        );
        out.iter().map(|c| (c.hit.t, c.touch)).collect::<Vec<_>>()
    };
    use Touch::{Crossing, Graze};
    assert_eq!(
        run(Ray::new(v(0., 0., 5.), v(0., 0., -1.))),
        [(4.0, Crossing), (6.0, Crossing)]
    );
    assert_eq!(run(Ray::new(Vec3::ZERO, v(0., 0., -1.))), [(1.0, Crossing)]);
    // Tangent at (1, 0, 0): the discriminant is exactly 0.
    assert_eq!(run(Ray::new(v(1., 0., 5.), v(0., 0., -1.))), [(5.0, Graze)]);
    assert_eq!(run(Ray::new(v(1.0001, 0., 5.), v(0., 0., -1.))), []);
}
