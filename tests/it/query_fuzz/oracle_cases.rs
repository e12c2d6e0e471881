//! The checker's oracle on cases with known answers: it must accept the right answers and
//! refuse the wrong ones (a false hit, a lost hit, the back of a sphere, a hole in a shared
//! edge), and agree with the hard-case suite's rational arithmetic (tests/hard_cases/exact.rs)
//! on seeded triangles and spheres.

use super::exact::{Q, exact_to_f64, ray_triangle};
use super::queries::expect::Expect;
use super::queries::oracle::{Class, Frame};
use super::queries::{self, Prim};
use super::{octahedron, ray, scene, sphere, tri};
use lumis_core::accel::Hit;
use lumis_core::geometry::PrimHit;
use lumis_core::math::{Ray, Vec3};
use num_traits::Signed;

/// The checker's verdict on the answer `hit` (primitive, t) and `occluded` for `ray`.
fn verdict(
    prims: &[Prim],
    ray: &Ray,
    hit: Option<(u32, f32)>,
    occluded: bool,
) -> Result<(), String> {
    let s = scene(prims);
    let frame = Frame::new(ray, &s.geometry.bounds());
    let e = Expect::new(&frame, &s.prims);
    let hit = hit.map(|(prim, t)| Hit {
        prim,
        hit: PrimHit {
            t,
            u: 0.0,
            v: 0.0,
            inner: 0,
        },
    });
    e.check(&frame, &s.prims, hit.as_ref(), occluded)
}

fn class(p: Prim, ray: &Ray) -> Class {
    let s = scene(&[p]);
    Frame::new(ray, &s.geometry.bounds()).classify(&p).0
}

fn err_contains(r: Result<(), String>, what: &str) {
    match r {
        Err(e) if e.contains(what) => {}
        other => panic!("expected an error containing {what:?}, got {other:?}"),
    }
}

const TRI: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

#[test]
fn a_ray_through_a_triangles_interior_is_a_clear_hit_at_the_exact_t() {
    let t = tri(TRI[0], TRI[1], TRI[2]);
    let r = ray([0.25, 0.25, 1.0], [0.0, 0.0, -1.0]);
    match class(t, &r) {
        Class::Hit(roots) => assert_eq!(roots[0].t, 1.0),
        other => panic!("{other:?}"),
    }
    verdict(&[t], &r, Some((0, 1.0)), true).unwrap();
    err_contains(verdict(&[t], &r, None, false), "lost hit");
    err_contains(
        verdict(&[t], &r, Some((0, 1.0)), false),
        "occluded is false",
    );
    err_contains(
        verdict(&[t], &r, Some((0, 1.5)), true),
        "not within tolerance",
    );
    // Behind the range: no hit is right, a hit is not.
    let short = Ray { t_max: 0.5, ..r };
    verdict(&[t], &short, None, false).unwrap();
    err_contains(verdict(&[t], &short, None, true), "occluded is true");
    // The same from 1e30 away: t = 1e30 - 1, which is 1e30 in f32.
    let far = ray([0.25, 0.25, 1e30], [0.0, 0.0, -1.0]);
    verdict(&[t], &far, Some((0, 1e30)), true).unwrap();
    err_contains(verdict(&[t], &far, None, false), "lost hit");
}

#[test]
fn a_ray_aimed_off_a_far_mesh_is_a_clear_miss() {
    // From 1e30, 1e-3 rad off the triangle: misses it by 1e27.
    let t = tri(TRI[0], TRI[1], TRI[2]);
    let r = ray([0.25, 0.25, 1e30], [1e-3, 0.0, -1.0]);
    assert!(matches!(class(t, &r), Class::Miss));
    verdict(&[t], &r, None, false).unwrap();
    err_contains(verdict(&[t], &r, Some((0, 1e30)), true), "false hit");
    err_contains(verdict(&[t], &r, None, true), "occluded is true");
}

#[test]
fn a_ray_through_a_shared_edge_must_hit_one_triangle_or_both() {
    let (a, b, c, d) = (
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    );
    let quad = [tri(a, b, c), tri(a, c, d)];
    // Aimed exactly at the diagonal's midpoint: on the shared edge of both.
    let r = ray([0.3, -0.2, 2.0], [0.2, 0.7, -2.0]);
    for p in quad {
        assert!(
            matches!(class(p, &r), Class::Ambiguous { .. }),
            "{:?}",
            class(p, &r)
        );
    }
    verdict(&quad, &r, Some((0, 1.0)), true).unwrap();
    verdict(&quad, &r, Some((1, 1.0)), true).unwrap();
    err_contains(verdict(&quad, &r, None, false), "share an edge");
    // Lumis's own answer passes the whole checker.
    queries::check(&scene(&quad), &[r]);
    // Two triangles on the same side of the edge (folded over): no promise.
    let folded = [tri(a, b, c), tri(a, c, [0.5, 0.0, 0.0])];
    verdict(&folded, &r, None, false).unwrap();
}

#[test]
fn the_front_of_a_sphere_is_the_answer_not_its_back() {
    let s = sphere([0.0, 0.0, 0.0], 1.0);
    let r = ray([0.0, 0.0, 10.0], [0.0, 0.0, -1.0]);
    match class(s, &r) {
        Class::Hit(roots) => assert_eq!((roots[0].t, roots[1].t), (9.0, 11.0)),
        other => panic!("{other:?}"),
    }
    verdict(&[s], &r, Some((0, 9.0)), true).unwrap();
    err_contains(verdict(&[s], &r, Some((0, 11.0)), true), "wrong order");
    err_contains(
        verdict(&[s], &r, Some((0, 10.0)), true),
        "not within tolerance",
    );
    // From inside, the exit is the answer.
    let inside = ray([0.0, 0.0, 0.5], [0.0, 0.0, -1.0]);
    verdict(&[s], &inside, Some((0, 1.5)), true).unwrap();
    // From 1e19 straight at the centre: the roots 1e19 -+ 1 are one f32, 1e19.
    let far = ray([0.0, 0.0, 1e19], [0.0, 0.0, -1.0]);
    verdict(&[s], &far, Some((0, 1e19)), true).unwrap();
    err_contains(verdict(&[s], &far, None, false), "lost hit");
}

#[test]
fn the_front_face_of_a_far_sphere_mesh_is_the_answer() {
    // From (1e19, 1e19, 1e19) with d = -o: front face 0 at t = 1 - 1/3e19, back face 7 at
    // t = 1 + 1/3e19, both 1.0 in f32; only the exact crossing tells them apart.
    let o = [1e19f32; 3];
    let r = ray(o, o.map(|x| -x));
    let mesh = octahedron();
    verdict(&mesh, &r, Some((0, 1.0)), true).unwrap();
    err_contains(verdict(&mesh, &r, Some((7, 1.0)), true), "wrong primitive");
    err_contains(verdict(&mesh, &r, None, false), "lost hit");
}

#[test]
fn a_tangent_ray_may_hit_or_miss_but_only_at_the_tangent_point() {
    let s = sphere([0.0, 0.0, 0.0], 1.0);
    let r = ray([1.0, 0.0, -5.0], [0.0, 0.0, 1.0]);
    assert!(matches!(class(s, &r), Class::Ambiguous { .. }));
    verdict(&[s], &r, Some((0, 5.0)), true).unwrap();
    verdict(&[s], &r, None, false).unwrap();
    err_contains(verdict(&[s], &r, Some((0, 3.0)), true), "outside");
}

#[test]
fn degenerate_and_parallel_triangles_are_ambiguous_only_near_the_line() {
    let line = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]);
    let through = ray([0.5, 0.0, 1.0], [0.0, 0.0, -1.0]);
    assert!(matches!(class(line, &through), Class::Ambiguous { .. }));
    let away = ray([0.5, 1.0, 1.0], [0.0, 0.0, -1.0]);
    assert!(matches!(class(line, &away), Class::Miss));
    let flat = tri(TRI[0], TRI[1], TRI[2]);
    let in_plane = ray([-1.0, 0.25, 0.0], [1.0, 0.0, 0.0]);
    assert!(matches!(class(flat, &in_plane), Class::Ambiguous { .. }));
    let above = ray([-1.0, 0.25, 0.5], [1.0, 0.0, 0.0]);
    assert!(matches!(class(flat, &above), Class::Miss));
}

/// splitmix64, for the seeded comparisons below.
fn next(s: &mut u64) -> u64 {
    *s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *s;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn small(s: &mut u64) -> f32 {
    (next(s) % 17) as f32 / 4.0 - 2.0
}

fn point(s: &mut u64) -> Vec3 {
    Vec3::new(small(s), small(s), small(s))
}

#[test]
fn triangle_classes_agree_with_rational_arithmetic() {
    let mut s = 7u64;
    let (mut hits, mut misses) = (0, 0);
    for _ in 0..3000 {
        let p = [point(&mut s), point(&mut s), point(&mut s)];
        let (o, d) = (point(&mut s), point(&mut s));
        if d == Vec3::ZERO {
            continue;
        }
        let prim = Prim::Triangle(p);
        let r = Ray::new(o, d);
        let exact = ray_triangle(o, d, p);
        match class(prim, &r) {
            Class::Hit(roots) => {
                let e = exact.expect("a clear hit is a hit in exact arithmetic");
                assert!(!e.on_boundary());
                let t = exact_to_f64(&e.t);
                assert!((roots[0].t - t).abs() <= 1e-15 * t.abs(), "{t} {roots:?}");
                hits += 1;
            }
            Class::Miss => {
                assert!(
                    exact.is_none(),
                    "a clear miss is a miss in exact arithmetic"
                );
                misses += 1;
            }
            Class::Ambiguous { .. } => {}
        }
    }
    assert!(hits > 100 && misses > 1000, "{hits} hits, {misses} misses");
}

#[test]
fn sphere_classes_and_roots_agree_with_rational_arithmetic() {
    let mut s = 11u64;
    let mut hits = 0;
    for _ in 0..2000 {
        let (c, o, d) = (point(&mut s), point(&mut s), point(&mut s));
        let radius = (next(&mut s) % 8 + 1) as f32 / 4.0;
        if d == Vec3::ZERO {
            continue;
        }
        let r = Ray::new(o, d);
        // The exact sign of |o + t d - c|^2 - r^2 at a rational t.
        let value = |t: f64| {
            let t = Q::from_float(t).unwrap();
            super::exact::sphere_value(o, d, c, radius, &t)
        };
        match class(sphere(c.to_array(), radius), &r) {
            Class::Hit(roots) => {
                hits += 1;
                let vertex = roots[0].t / 2.0 + roots[1].t / 2.0;
                assert!(value(vertex).is_negative(), "the chord's middle is inside");
                for root in roots {
                    // A sign change within a relative 1e-12 of each root.
                    let e = 1e-12 * root.t.abs().max(1e-3);
                    let (a, b) = (value(root.t - e), value(root.t + e));
                    assert!(a.signum() != b.signum(), "no root near {}", root.t);
                }
            }
            Class::Miss => {
                let closest = (c - o).dot(d) as f64 / d.length_squared() as f64;
                assert!(value(closest).is_positive(), "a clear miss stays outside");
            }
            Class::Ambiguous { .. } => {}
        }
    }
    assert!(hits > 300, "{hits} hits");
}

#[test]
fn crossing_offsets_order_crossings_as_their_parameters_do() {
    // Near the origin `f64` resolves every `t`: the offsets from the common reference must
    // differ exactly as the parameters do, across spheres and triangles.
    let mut s = 13u64;
    let mut compared = 0;
    for _ in 0..300 {
        let prims: Vec<Prim> = (0..4)
            .map(|k| {
                if k % 2 == 0 {
                    Prim::Triangle([point(&mut s), point(&mut s), point(&mut s)])
                } else {
                    let r = (next(&mut s) % 8 + 1) as f32 / 4.0;
                    sphere(point(&mut s).to_array(), r)
                }
            })
            .collect();
        let Some(sc) = queries::Scene::build(&prims) else {
            continue;
        };
        let d = point(&mut s);
        if d == Vec3::ZERO {
            continue;
        }
        let r = Ray::new(point(&mut s), d);
        let frame = Frame::new(&r, &sc.geometry.bounds());
        let roots: Vec<_> = sc
            .prims
            .iter()
            .filter_map(|p| match frame.classify(p).0 {
                Class::Hit(roots) => Some(roots),
                _ => None,
            })
            .flatten()
            .collect();
        for a in &roots {
            for b in &roots {
                let (dt, ddt) = (a.t - b.t, a.dt - b.dt);
                assert!(
                    (dt - ddt).abs() <= 1e-12 * (1.0 + a.t.abs() + b.t.abs()),
                    "{a:?} {b:?}"
                );
                compared += 1;
            }
        }
    }
    assert!(compared > 100, "{compared}");
}

/// Seeded input 3077: a ray with `|d| = 2.4e26` grazes a sliver (z from -31.7 to 1e5; the
/// cosine between ray and normal is 1.7e-5) just inside its edge 1-2, at `t = 2.1175823e-22`
/// in exact arithmetic, in front of a sphere (primitive 2) crossed at `t = 4.2306e-22`.
/// lumis returns the sliver. The checker once called that the wrong primitive: the sphere's
/// crossing offsets had the wrong sign, so its front looked 2.1e-22 *before* the scene's
/// reference point while every printed `t` was right.
#[test]
fn a_grazed_sliver_in_front_of_a_sphere_is_the_answer() {
    let v = |b: [u32; 3]| b.map(f32::from_bits);
    let (a, b, c) = (
        v([0xbf988f8b, 0x40002c80, 0x47c35000]),
        v([0xbeaaca2b, 0xbfe4e1c0, 0x47c35018]),
        v([0x36b0bfa3, 0x24f8abad, 0xc1fd5c14]),
    );
    let (d, e) = (
        v([0xbfeaf54b, 0x400c6180, 0x47c34f49]),
        v([0xbbf901f6, 0xb8fcce5e, 0xb60a34c8]),
    );
    let prims = [
        sphere(c, f32::from_bits(0x340a30e3)),
        tri(a, b, c),
        sphere(c, f32::from_bits(0x42d59f80)),
        tri(a, b, v([0xbf126e15, 0x3ec35000, 0x47c35165])),
        tri(d, e, e),
        sphere(d, f32::from_bits(0x2e4599f0)),
    ];
    let r = ray(
        v([0xbfc9638b, 0xbe435000, 0x47c350cc]),
        v([0x63b40a5c, 0xe3340dc0, 0xeb436156]),
    );
    // Rational arithmetic (Cramer's rule): a hit just inside the edge opposite corner 0.
    let Prim::Triangle(corners) = prims[1] else {
        unreachable!()
    };
    let hit = ray_triangle(r.origin, r.dir, corners).expect("an exact hit");
    let t = exact_to_f64(&hit.t);
    assert!((t - 2.1175823e-22).abs() < 1e-29, "{t:e}");
    assert!(!hit.on_boundary());
    // The oracle: the sliver may be hit (within delta of its edge) at that t; the sphere is
    // clearly hit behind it, and both offsets are their t minus the same reference.
    let s = scene(&prims);
    let frame = Frame::new(&r, &s.geometry.bounds());
    match frame.classify(&prims[1]).0 {
        Class::Hit(roots) => assert!((roots[0].t - t).abs() <= frame.tol(&roots[0])),
        Class::Ambiguous { lo, hi, dt_lo } => {
            assert!(lo < t && t < hi, "[{lo:e}, {hi:e}]");
            assert!((lo - dt_lo - frame.t_ref).abs() < 1e-12 * frame.t_ref);
        }
        Class::Miss => panic!("the sliver is crossed"),
    }
    let Class::Hit(sphere_roots) = frame.classify(&prims[2]).0 else {
        panic!("the sphere is clearly hit");
    };
    let front = sphere_roots[0];
    assert!((front.t - 4.230583850694954e-22).abs() < 1e-35, "{front:?}");
    assert!((front.t - front.dt - frame.t_ref).abs() < 1e-12 * frame.t_ref);
    assert!(
        t - frame.t_ref < front.dt,
        "the sliver's offset is the smaller"
    );
    // lumis's answer passes; the sphere's back does not.
    verdict(&prims, &r, Some((1, 2.1175822e-22)), true).unwrap();
    verdict(&prims, &r, Some((2, front.t as f32)), true).unwrap();
    err_contains(
        verdict(&prims, &r, Some((2, sphere_roots[1].t as f32)), true),
        "wrong order",
    );
    queries::check(&s, &[r]);
}
