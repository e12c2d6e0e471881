//! All hits along a ray (`World::all_hits`): each surface crossing counted once, touches that
//! do not cross flagged as grazes (the rule: docs/hard-cases.md, "All hits along a ray").
//!
//! - parity: on closed meshes (cube, dented cube, octahedron, tetrahedron, an octagonal
//!   bipyramid fan, a jittered icosphere, the knot asset), with integer-coordinate rays through
//!   exact vertices, edge points and face points, rays along edges and in faces, and seeded
//!   random rays, every two points of a ray between reported hits are on the same side of the
//!   surface exactly when an even number of crossings (grazes not counted) lies between them,
//!   by an exact rational inside/outside oracle (`all_hits/oracle.rs`);
//! - the first hit's `t` is the nearest-hit query's;
//! - every accelerator and traversal returns brute force's hits bit for bit;
//! - silhouette vertices and edges, rays along a surface and tangent spheres are grazes.

use crate::common;
mod meshes;
pub(crate) mod oracle;
mod touches;

use common::{Rng, scenes};
use lumis_core::accel::TraversalStats;
use lumis_core::accel::{AccelKind, BuildOptions, PAPER_SEGMENT_MAX, SegmentParams, Traversal};
use lumis_core::geometry::{Mesh, Primitive, Sphere};
use lumis_core::math::{Ray, Vec3};
use lumis_core::scene::{Scene, SurfaceHit, World};
use meshes::{bipyramid, cube, octahedron, scene, targets, tetrahedron, triangles, v, world};
use num_rational::BigRational;
use oracle::{Side, classify, q};

/// What the parity checks covered.
#[derive(Default, Debug)]
struct Tally {
    rays: usize,
    pairs: usize,
    crossings: usize,
    grazes: usize,
    surface_samples: usize,
}

fn hits(world: &World, ray: &Ray) -> Vec<SurfaceHit> {
    world.all_hits(ray, &mut TraversalStats::default())
}

/// Checks one ray: sorted hits, the nearest hit first, and parity against the oracle at
/// points between the reported hits (far enough from them that rounding cannot matter).
fn check_ray(name: &str, world: &World, tris: &[[Vec3; 3]], ray: Ray, tally: &mut Tally) {
    let h = hits(world, &ray);
    assert!(
        h.windows(2)
            .all(|w| w[0].t < w[1].t || (w[0].t == w[1].t && w[0].prim < w[1].prim)),
        "{name}: not sorted: {h:?}"
    );
    let nearest = world.intersect_hit(&ray, &mut TraversalStats::default());
    assert_eq!(
        nearest.map(|n| n.hit.t.to_bits()),
        h.first().map(|f| f.t.to_bits()),
        "{name}: the first hit is not the nearest hit for {ray:?}: {nearest:?} vs {h:?}"
    );
    let mut cuts: Vec<f32> = h.iter().map(|h| h.t).collect();
    cuts.dedup();
    let last = cuts.last().copied().unwrap_or(0.0).max(0.0);
    let mut ends = vec![ray.t_min];
    ends.extend(&cuts);
    ends.push(last * 2.0 + 64.0);
    let two = BigRational::from_integer(2.into());
    let mut samples = Vec::new();
    for w in ends.windows(2) {
        let (lo, hi) = (w[0], w[1]);
        if hi - lo > 2f32.powi(-12) * lo.abs().max(hi.abs()).max(1.0) {
            let t = (q(lo) + q(hi)) / &two;
            match classify(ray.origin, ray.dir, &t, tris) {
                Side::Surface => tally.surface_samples += 1,
                side => samples.push((t, side)),
            }
        }
    }
    for w in samples.windows(2) {
        let ((ta, sa), (tb, sb)) = (&w[0], &w[1]);
        let between = h
            .iter()
            .filter(|h| !h.graze && q(h.t) > *ta && q(h.t) < *tb)
            .count();
        assert_eq!(
            sa != sb,
            between % 2 == 1,
            "{name}: {sa:?} at t = {ta}, {sb:?} at t = {tb}, {between} crossings between, \
             ray {ray:?}, hits {h:?}"
        );
        tally.pairs += 1;
    }
    tally.rays += 1;
    tally.crossings += h.iter().filter(|h| !h.graze).count();
    tally.grazes += h.iter().filter(|h| h.graze).count();
}

fn small_int_dir(rng: &mut Rng) -> Vec3 {
    loop {
        let mut c = || rng.below(7) as f32 - 3.0;
        let d = v(c(), c(), c());
        if d != Vec3::ZERO {
            return d;
        }
    }
}

/// Integer-coordinate rays through exact targets, lines through two targets (along edges and
/// in faces) and seeded random rays, over one closed mesh with integer vertices.
fn check_exact_mesh(name: &str, m: Mesh, seed: u64) -> Tally {
    let tris = triangles(&m);
    let aims = targets(&m);
    let world = world(vec![m], &[]);
    let mut rng = Rng::new(seed);
    let mut tally = Tally::default();
    let pick = |rng: &mut Rng| aims[rng.below(aims.len())];
    for i in 0..600 {
        let ray = match i % 4 {
            // From an integer point, exactly through a target at t = 1.
            0 => {
                let o = v(
                    rng.below(13) as f32 - 6.0,
                    rng.below(13) as f32 - 6.0,
                    rng.below(13) as f32 - 6.0,
                );
                let target = pick(&mut rng);
                if o == target {
                    continue;
                }
                Ray::new(o, target - o)
            }
            // Through a target at t = 0, both ways.
            1 => Ray {
                t_min: -16.0,
                ..Ray::new(pick(&mut rng), small_int_dir(&mut rng))
            },
            // The line through two targets: along edges, across faces, in their planes.
            2 => {
                let (a, b) = (pick(&mut rng), pick(&mut rng));
                if a == b {
                    continue;
                }
                Ray {
                    t_min: -16.0,
                    ..Ray::new(a, b - a)
                }
            }
            _ => Ray::new(
                rng.in_box(&lumis_core::math::Aabb::new(
                    Vec3::splat(-6.0),
                    Vec3::splat(6.0),
                )),
                rng.unit_vector(),
            ),
        };
        check_ray(name, &world, &tris, ray, &mut tally);
    }
    println!("{name}: {tally:?}");
    assert!(tally.rays > 500 && tally.pairs > 600, "{name}: {tally:?}");
    tally
}

#[test]
fn crossings_have_the_exact_parity_on_integer_meshes_through_edges_and_vertices() {
    let mut grazes = 0;
    for (name, m, seed) in [
        ("cube", cube(false, false), 1),
        ("cube, other diagonals", cube(true, false), 2),
        ("dented cube", cube(false, true), 3),
        ("octahedron", octahedron(), 4),
        ("tetrahedron", tetrahedron(), 5),
        ("bipyramid fan", bipyramid(), 6),
    ] {
        grazes += check_exact_mesh(name, m, seed).grazes;
    }
    // Lines through two vertices or edge points of a convex mesh graze it often.
    assert!(grazes > 100, "{grazes}");
}

#[test]
fn crossings_have_the_exact_parity_on_an_icosphere_and_the_knot_asset() {
    let ico = scenes::icosphere(2, 0.05, &mut Rng::new(9));
    let knot = lumis_io::formats::load(std::path::Path::new("assets/knot.obj"))
        .expect("the knot asset loads");
    let knot_mesh = knot.geometry().meshes()[0].clone();
    for (name, m, rays) in [("icosphere", ico, 400), ("knot", knot_mesh, 120)] {
        let tris = triangles(&m);
        let p = m.positions().to_vec();
        let idx = m.indices().to_vec();
        let b = m.bounds();
        let world = world(vec![m], &[]);
        let mut rng = Rng::new(17);
        let mut tally = Tally::default();
        for i in 0..rays {
            let [a, c, _] = idx[rng.below(idx.len())];
            let (a, c) = (p[a as usize], p[c as usize]);
            let ray = match i % 3 {
                // Exactly through a vertex at t = 0, any direction.
                0 => Ray {
                    t_min: -8.0,
                    ..Ray::new(a, rng.unit_vector())
                },
                // Exactly through a vertex, close along one of its edges.
                1 => Ray {
                    t_min: -8.0,
                    ..Ray::new(a, c - a)
                },
                _ => Ray::new(rng.in_box(&b) * 1.5, rng.unit_vector()),
            };
            check_ray(name, &world, &tris, ray, &mut tally);
        }
        println!("{name}: {tally:?}");
        assert!(tally.pairs > rays, "{name}: {tally:?}");
    }
}

/// `(t, prim, object, u, v, normal, kind, graze)` as bits.
type HitBits = (u32, u32, u32, u32, u32, [u32; 3], Primitive, bool);

fn bits(h: &[SurfaceHit]) -> Vec<HitBits> {
    h.iter()
        .map(|h| {
            (
                h.t.to_bits(),
                h.prim,
                h.object,
                h.u.to_bits(),
                h.v.to_bits(),
                h.normal.to_array().map(f32::to_bits),
                h.primitive,
                h.graze,
            )
        })
        .collect()
}

#[test]
fn every_accelerator_and_traversal_returns_brute_forces_hits_bit_for_bit() {
    let assets = [
        "assets/knot.obj",
        "assets/mixed_faces.obj",
        "assets/illum_modes.obj",
    ];
    let mut scenes: Vec<(String, Scene)> = assets
        .iter()
        .map(|a| {
            let s = lumis_io::formats::load(std::path::Path::new(a)).expect("asset loads");
            (a.to_string(), s)
        })
        .collect();
    scenes.push((
        "integer meshes and spheres".into(),
        scene(
            vec![cube(false, true), octahedron(), bipyramid()],
            &[
                Sphere {
                    center: v(2., 2., 0.),
                    radius: 1.,
                },
                Sphere {
                    center: v(0., 0., 3.),
                    radius: 0.5,
                },
            ],
        ),
    ));
    let traversals = [
        Traversal::Ordered,
        Traversal::Exhaustive,
        Traversal::Segments(SegmentParams {
            init: 0.25,
            max: 2.0,
        }),
        Traversal::Segments(SegmentParams {
            init: 1.0,
            max: PAPER_SEGMENT_MAX,
        }),
    ];
    for (name, s) in scenes {
        let g = s.geometry();
        let b = g.bounds();
        let verts: Vec<Vec3> = g
            .meshes()
            .iter()
            .flat_map(|m| m.positions().to_vec())
            .collect();
        let mut rng = Rng::new(23);
        let rays: Vec<Ray> = (0..300)
            .map(|i| match i % 3 {
                0 => Ray {
                    t_min: -4.0,
                    ..Ray::new(verts[rng.below(verts.len())], rng.unit_vector())
                },
                1 => {
                    let o = rng.in_box(&b) * 2.0;
                    Ray::new(o, verts[rng.below(verts.len())] - o)
                }
                _ => Ray::new(rng.in_box(&b) * 1.5, rng.unit_vector()),
            })
            .collect();
        let brute = World::build(s.clone(), AccelKind::Brute, &BuildOptions::default());
        let want: Vec<_> = rays.iter().map(|r| bits(&hits(&brute, r))).collect();
        let found: usize = want.iter().map(Vec::len).sum();
        assert!(found > 50, "{name}: only {found} hits");
        let paths = crate::common::simd::simd_paths(&format!("all hits, {name}"));
        for kind in AccelKind::ALL {
            for leaf in [1, kind.default_leaf_size()] {
                let opts = BuildOptions {
                    max_leaf_size: leaf,
                    ..Default::default()
                };
                let built = World::build(s.clone(), kind, &opts);
                for t in traversals {
                    let w = built.clone().with_traversal(t);
                    for path in paths.each() {
                        for (r, want) in rays.iter().zip(&want) {
                            assert_eq!(
                                &bits(&hits(&w, r)),
                                want,
                                "{name}: {kind:?} leaf {leaf} {t:?} {} ray {r:?}",
                                path.name()
                            );
                        }
                    }
                }
            }
        }
    }
}

/// `(t, graze)` of every hit.
fn kinds(world: &World, o: Vec3, d: Vec3) -> Vec<(f32, bool)> {
    hits(world, &Ray::new(o, d))
        .iter()
        .map(|h| (h.t, h.graze))
        .collect()
}

#[test]
fn silhouette_vertices_and_edges_surface_rays_and_tangents_are_grazes() {
    let cube = world(vec![cube(false, false)], &[]);
    // Only the vertex (2, 2, 2) / only the edge point (2, 2, 0) is touched.
    assert_eq!(kinds(&cube, v(0., 4., 2.), v(1., -1., 0.)), [(2.0, true)]);
    assert_eq!(kinds(&cube, v(0., 4., 0.), v(1., -1., 0.)), [(2.0, true)]);
    // In through a vertex, out through the opposite one; in and out through edges.
    let crossing = [(2.0, false), (6.0, false)];
    assert_eq!(kinds(&cube, v(-4., -4., -4.), v(1., 1., 1.)), crossing);
    assert_eq!(kinds(&cube, v(0., -4., -4.), v(0., 1., 1.)), crossing);
    // Along an edge: the displaced ray (+eps along y, +eps^2 along z for a +x ray) passes
    // inside the edge y = z = -2 and outside the edge y = z = 2.
    assert_eq!(kinds(&cube, v(-4., -2., -2.), v(1., 0., 0.)), crossing);
    assert_eq!(
        kinds(&cube, v(-4., 2., 2.), v(1., 0., 0.)),
        [(2.0, true), (6.0, true)]
    );

    let octa = world(vec![octahedron()], &[]);
    assert_eq!(kinds(&octa, v(3., -2., 0.), v(0., 1., 0.)), [(2.0, true)]);
    assert_eq!(
        kinds(&octa, v(5., 0., 0.), v(-1., 0., 0.)),
        [(2.0, false), (8.0, false)]
    );
    assert_eq!(kinds(&octa, v(1.5, 1.5, -2.), v(0., 0., 1.)), [(2.0, true)]);
    assert_eq!(
        kinds(&octa, v(3.5, 3.5, 0.), v(-1., -1., 0.)),
        [(2.0, false), (5.0, false)]
    );

    let fan = world(vec![bipyramid()], &[]);
    // Down through the apex of eight triangles, out through the other.
    assert_eq!(
        kinds(&fan, v(0., 0., 5.), v(0., 0., -1.)),
        [(2.0, false), (8.0, false)]
    );
    // Across the apex horizontally: a graze.
    assert_eq!(kinds(&fan, v(-2., 1., 3.), v(2., -1., 0.)), [(1.0, true)]);

    let ball = world(
        vec![],
        &[Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        }],
    );
    assert_eq!(kinds(&ball, v(1., 0., 5.), v(0., 0., -1.)), [(5.0, true)]);
    assert_eq!(
        kinds(&ball, v(0.5, 0., 5.), v(0., 0., -1.)),
        [(5.0 - 0.75f32.sqrt(), false), (5.0 + 0.75f32.sqrt(), false)]
    );
}
