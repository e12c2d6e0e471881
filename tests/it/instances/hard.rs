//! Hard cases of instancing: a closed icosphere placed far from the origin, mirrored, scaled
//! from 1e-6 to 1e6, rotated and stretched, shot from its centre through its vertices and edge
//! midpoints (where a non-watertight test leaks) and from outside at them. Never a leak, the
//! same answer from brute force over instances and the wide hierarchy, and `t` within the
//! documented bound of an independent `f64` oracle: the world triangles (the placement applied
//! to the prototype's `f32` corners in `f64`) met by the caller's `f32` ray in `f64`.

use super::fixtures::camera;
use crate::common::{Rng, scenes};
use glam::{DAffine3, DQuat, DVec3};
use lumis_core::accel::{AccelKind, BuildOptions, TraversalStats};
use lumis_core::geometry::Mesh;
use lumis_core::material::Material;
use lumis_core::math::Ray;
use lumis_core::scene::{Part, Scene, SceneBuilder, Shape, World};

/// One icosphere instance placed by `to_world`.
fn scene(mesh: &Mesh, to_world: DAffine3) -> Scene {
    let mut b = SceneBuilder::new();
    let m = b.add_material(Material::default());
    let proto = b.add_prototype(vec![Part {
        name: "ball".into(),
        shape: Shape::Mesh(mesh.clone()),
        material: m,
    }]);
    b.add_instance(proto, "ball", to_world);
    b.build(camera()).expect("within the limits")
}

/// The nearest `t > 0` of `ray` (as given, in `f64`) with the placed mesh, by Moeller-Trumbore
/// in `f64` over the world triangles, with that triangle's unit normal; none when it misses
/// every one.
fn oracle(mesh: &Mesh, to_world: &DAffine3, ray: &Ray) -> Option<(f64, DVec3)> {
    let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
    let mut best: Option<(f64, DVec3)> = None;
    for tri in 0..mesh.triangle_count() as u32 {
        let [a, b, c] = mesh
            .corners(tri)
            .map(|p| to_world.transform_point3(p.as_dvec3()));
        let (e1, e2) = (b - a, c - a);
        let p = d.cross(e2);
        let det = e1.dot(p);
        if det == 0.0 {
            continue;
        }
        let s = o - a;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = d.dot(q) / det;
        // A little slack: the oracle itself rounds, and a ray through an edge must count.
        let slack = 1e-9;
        if u < -slack || v < -slack || u + v > 1.0 + slack {
            continue;
        }
        let t = e2.dot(q) / det;
        if t > 0.0 && best.is_none_or(|b| t < b.0) {
            best = Some((t, e1.cross(e2).normalize()));
        }
    }
    best
}

/// The placements: far translations, mirrors, scales from 1e-6 to 1e6, a stretch.
fn placements() -> Vec<(&'static str, DAffine3)> {
    let rot = DQuat::from_euler(glam::EulerRot::XYZ, 0.4, 1.3, -0.7);
    let srt = |s: DVec3, r: DQuat, t: DVec3| DAffine3::from_scale_rotation_translation(s, r, t);
    vec![
        ("far 1e5", srt(DVec3::ONE, rot, DVec3::new(1e5, -3e4, 7e4))),
        ("far 1e7", srt(DVec3::ONE, rot, DVec3::new(1e7, 1e7, -1e7))),
        (
            "mirror x",
            srt(DVec3::new(-1.0, 1.0, 1.0), rot, DVec3::new(2.0, 0.0, 0.0)),
        ),
        (
            "mirror xyz",
            srt(DVec3::splat(-2.0), rot, DVec3::new(0.0, 1.0, 0.0)),
        ),
        (
            "scale 1e-6",
            srt(DVec3::splat(1e-6), rot, DVec3::new(0.3, 0.2, 0.1)),
        ),
        (
            "scale 1e-3 far",
            srt(DVec3::splat(1e-3), rot, DVec3::new(50.0, 0.0, 0.0)),
        ),
        ("scale 1e3", srt(DVec3::splat(1e3), rot, DVec3::ZERO)),
        (
            "scale 1e6",
            srt(DVec3::splat(1e6), rot, DVec3::new(1e6, 0.0, 0.0)),
        ),
        (
            "stretch",
            srt(DVec3::new(0.01, 1.0, 100.0), rot, DVec3::new(1.0, 2.0, 3.0)),
        ),
        (
            "mirror 1e-6",
            srt(DVec3::new(1e-6, -1e-6, 1e-6), rot, DVec3::ZERO),
        ),
    ]
}

#[test]
fn instanced_closed_meshes_never_leak_and_agree_with_the_f64_oracle() {
    let mesh = scenes::icosphere(2, 0.0, &mut Rng::new(9));
    let mut rng = Rng::new(4);
    for (name, to_world) in placements() {
        let s = scene(&mesh, to_world);
        let brute = World::build(s.clone(), AccelKind::Brute, &BuildOptions::default());
        let wide = World::build(s, AccelKind::Sah, &BuildOptions::default());
        let centre = to_world.translation;
        let scale = to_world
            .matrix3
            .x_axis
            .length()
            .max(to_world.matrix3.z_axis.length());
        let mut stats = TraversalStats::default();
        let (mut checked, mut worst) = (0, 0.0f64);
        // From the centre (inside a closed mesh: every ray must hit) through every vertex and
        // the midpoints of every triangle's edges, where a test that is not watertight leaks;
        // from outside, 3 radii away, at every triangle's centroid (through a vertex from
        // outside, a ray may only graze the silhouette).
        let mut targets = Vec::new();
        for tri in 0..mesh.triangle_count() as u32 {
            let c = mesh
                .corners(tri)
                .map(|p| to_world.transform_point3(p.as_dvec3()));
            for t in [c[0], (c[0] + c[1]) * 0.5, (c[1] + c[2]) * 0.5] {
                targets.push((centre, t));
            }
            let outside = centre + rng.unit_vector().as_dvec3() * 3.0 * scale;
            targets.push((outside, (c[0] + c[1] + c[2]) / 3.0));
        }
        for (k, (from, target)) in targets.iter().enumerate() {
            {
                let from = *from;
                let origin = from.as_vec3();
                let dir = (*target - origin.as_dvec3()).as_vec3();
                if dir.length_squared() == 0.0 || !dir.is_finite() {
                    continue;
                }
                let ray = Ray::new(origin, dir);
                let want = brute.trace(&ray, &mut stats).map(|t| t.caller_hit());
                let got = wide.trace(&ray, &mut stats).map(|t| t.caller_hit());
                assert_eq!(
                    got, want,
                    "{name}: target {k} from {from}: wide differs from brute"
                );
                let Some((oracle_t, normal)) = oracle(&mesh, &to_world, &ray) else {
                    continue;
                };
                let hit = want.unwrap_or_else(|| {
                    panic!("{name}: ray {ray:?} leaks (the oracle hits at t = {oracle_t})")
                });
                // The bound: the object-space ray rounds once (half an ulp of its origin and
                // direction), which moves the line by ~2^-24 of the distance travelled and of
                // the origin's offset from the instance, times the placement's stretch.
                let stretch = to_world
                    .matrix3
                    .x_axis
                    .length()
                    .max(to_world.matrix3.z_axis.length())
                    / to_world
                        .matrix3
                        .x_axis
                        .length()
                        .min(to_world.matrix3.y_axis.length())
                        .min(to_world.matrix3.z_axis.length());
                let travel = oracle_t * ray.dir.as_dvec3().length();
                let offset = (ray.origin.as_dvec3() - centre).length() + scale;
                // How far the reported point lies off the surface (along its normal): what the
                // rounding moves; along a grazing ray that is a far longer way in `t`.
                let error =
                    (hit.hit.t as f64 - oracle_t).abs() * ray.dir.as_dvec3().dot(normal).abs();
                let bound = 2.0 * f32::EPSILON as f64 * (travel + offset) * stretch.max(1.0);
                worst = worst.max(error / (travel + offset));
                assert!(
                    error <= bound,
                    "{name}: t {} vs oracle {oracle_t}: {error:e} beyond {bound:e} (ray {ray:?} from {from}, prim {} inner {})",
                    hit.hit.t,
                    hit.prim,
                    hit.hit.inner
                );
                checked += 1;
            }
        }
        assert!(checked > 400, "{name}: {checked} rays checked");
        eprintln!("{name}: {checked} rays, worst error {worst:e} of the distance scale");
    }
}

/// A singular placement is not refused: it is drawn flattened (the builder's `singular`
/// tests, `gltf_instancing_hidden`), since glTF files hide meshes with a zero scale.
#[test]
fn a_non_finite_or_out_of_range_placement_is_refused_by_name() {
    let mesh = scenes::icosphere(1, 0.0, &mut Rng::new(1));
    for (bad, what) in [
        (
            DAffine3::from_translation(DVec3::new(f64::NAN, 0.0, 0.0)),
            "non-finite",
        ),
        (DAffine3::from_translation(DVec3::new(1e30, 0.0, 0.0)), ""),
    ] {
        let mut b = SceneBuilder::new();
        let m = b.add_material(Material::default());
        let proto = b.add_prototype(vec![Part {
            name: "p".into(),
            shape: Shape::Mesh(mesh.clone()),
            material: m,
        }]);
        b.add_instance(proto, "bad one", bad);
        let err = b.build(camera()).expect_err("refused");
        assert_eq!(err.element, "instance \"bad one\"", "{err:?}");
        assert!(err.message.contains(what), "{err:?}");
    }
}
