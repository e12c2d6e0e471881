//! Arrays of placements, prototypes of several parts, ellipsoids, and `-D` on instances.

use super::{asset, error, hit, load, load_at, world};
use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::math::Vec3;
use lumis_core::scene::Scene;

/// 100 balls on a 10 x 10 grid, 2 apart: entry k at x = 2 (k mod 10), z = -2 (k div 10).
fn grid() -> String {
    let ts: Vec<String> = (0..100)
        .map(|k| format!("[{}.0, 0.0, {}.0]", 2 * (k % 10), -2 * (k / 10)))
        .collect();
    format!(
        r#"
[[sphere]]
name = "ball"
center = [0.0, 0.0, 0.0]
radius = 0.5

[[instance]]
of = "ball"
name = "grid"
translations = [{}]
"#,
        ts.join(", ")
    )
}

#[test]
fn translations_make_one_named_instance_each_and_hits_report_theirs() {
    let scene = load(&grid());
    assert_eq!(scene.geometry().instances().len(), 100);
    assert_eq!(
        scene.geometry().spheres().len(),
        0,
        "the ball is only a prototype"
    );
    let names: Vec<String> = scene.objects().iter().map(|o| o.name.clone()).collect();
    let expected: Vec<String> = (0..100).map(|k| format!("grid/{k}")).collect();
    assert_eq!(names, expected);
    let w = world(scene);
    for k in [0u32, 7, 37, 99] {
        let (x, z) = (2.0 * (k % 10) as f32, -2.0 * (k / 10) as f32);
        let (i, name) = hit(&w, Vec3::new(x, 10.0, z), Vec3::NEG_Y).expect("a hit");
        assert_eq!(i.instance, Some(k), "placement {k}");
        assert_eq!(name, format!("grid/{k}"));
        assert!((i.t - 9.5).abs() < 1e-4, "t {}", i.t);
        assert!((i.surface.p - Vec3::new(x, 0.5, z)).length() < 1e-4);
    }
    // Between the balls there is nothing.
    assert!(hit(&w, Vec3::new(1.0, 10.0, -1.0), Vec3::NEG_Y).is_none());
}

#[test]
fn a_model_of_several_objects_is_a_prototype_of_several_parts() {
    let text = format!(
        "[[mesh]]\nname = \"m\"\nfile = \"{}\"\n\n[[instance]]\nof = \"m\"\nname = \"left\"\n\
         translate = [-5.0, 0.0, 0.0]\n\n[[instance]]\nof = \"m\"\nmatrix = [2, 0, 0, 5,  0, 2, \
         0, 0,  0, 0, 2, 0,  0, 0, 0, 1]\n",
        asset("assets/mixed_faces.obj")
    );
    let scene = load(&text);
    let names: Vec<&str> = scene.objects().iter().map(|o| o.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "left/mixed",
            "left/quad",
            "instance1/mixed",
            "instance1/quad"
        ]
    );
    let flat = load(&format!(
        "[[mesh]]\nname = \"m\"\nfile = \"{}\"\n",
        asset("assets/mixed_faces.obj")
    ));
    let b = flat.geometry().bounds();
    let i = scene.geometry().instances();
    let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() < 1e-4;
    assert!(
        close(i[0].bounds.min, b.min - Vec3::X * 5.0),
        "{:?}",
        i[0].bounds
    );
    assert!(
        close(i[1].bounds.max, b.max * 2.0 + Vec3::X * 5.0),
        "{:?}",
        i[1].bounds
    );
}

/// An orthographic view down -Z of an 8 x 8 window onto the emissive unit ball `egg`, placed
/// by `placement`.
fn egg(placement: &str) -> String {
    format!(
        r#"
[render]
width = 128
height = 128
background = [0.0, 0.0, 0.0]
ambient = [0.0, 0.0, 0.0]

[camera]
type = "orthographic"
height = 8.0
position = [0.0, 0.0, 10.0]
look_at = [0.0, 0.0, 0.0]

[materials.glow]
diffuse = [0.0, 0.0, 0.0]
specular = [0.0, 0.0, 0.0]
emission = [1.0, 1.0, 1.0]

[[sphere]]
name = "unit"
center = [0.0, 0.0, 0.0]
radius = 1.0
material = "glow"

[[instance]]
of = "unit"
name = "egg"
{placement}
"#
    )
}

/// The covered pixels of `scene` rendered: their count and mean column.
fn coverage(scene: Scene) -> (usize, f64) {
    let film =
        crate::common::render::film(scene, (128, 128), AccelKind::Sah, &BuildOptions::default());
    let (mut n, mut x_sum) = (0usize, 0.0f64);
    for (i, p) in film.rgba().iter().enumerate() {
        if p.x > 0.5 {
            n += 1;
            x_sum += (i % 128) as f64 + 0.5;
        }
    }
    (n, x_sum / n.max(1) as f64)
}

#[test]
fn a_sphere_under_a_non_uniform_scale_renders_as_its_ellipsoid_and_d_moves_it() {
    let text = egg("scale = [2.0, 1.0, 1.0]\nrotate = [0.0, 0.0, 30.0]");
    let (n, centre) = coverage(load(&text));
    // The ellipse of semi-axes 2 and 1 covers pi * 2 * 1 of the 8 x 8 window.
    let pixel = (8.0f64 / 128.0).powi(2);
    let expected = std::f64::consts::PI * 2.0 / pixel;
    let rel = (n as f64 - expected).abs() / expected;
    eprintln!(
        "ellipse: {n} pixels, analytic {expected:.0}, {:.2}% off",
        rel * 100.0
    );
    assert!(rel < 0.02, "{n} pixels, expected {expected:.0}");
    assert!((centre - 64.0).abs() < 0.5, "centred: {centre}");
    // -D moves the instance: 1.25 units right is 20 pixels, the area unchanged.
    let moved = load_at(&text, &["instance.egg.translate=[1.25, 0, 0]"], None).unwrap();
    let (m, moved_centre) = coverage(moved);
    eprintln!("moved by -D: centre column {centre:.2} -> {moved_centre:.2}");
    assert!(
        (moved_centre - centre - 20.0).abs() < 0.5,
        "{centre} -> {moved_centre}"
    );
    assert!(m.abs_diff(n) < n / 100, "{n} vs {m}");
    // By index too, and an unknown instance is an error naming it.
    let by_index = load_at(&text, &["instance.0.translate=[1.25, 0, 0]"], None).unwrap();
    assert_eq!(coverage(by_index).0, m);
    let e = error(&text, &["instance.nope.translate=[1, 0, 0]"]);
    assert!(
        e.contains("-D instance.nope.translate") && e.contains("no element nope"),
        "{e}"
    );
}

#[test]
fn the_example_scene_places_its_ring_centre_and_grid() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/instances.toml");
    let scene = crate::common::render::load(&path);
    assert_eq!(scene.geometry().instances().len(), 8 + 1 + 21);
    let names: Vec<&str> = scene.objects().iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names[..3], ["ground", "ring/0", "ring/1"]);
    assert_eq!(names[9..11], ["centre", "grid/0"]);
    assert_eq!(names.last(), Some(&"grid/20"));
    // The centre knot mirrors: its placement's determinant is -0.8^3.
    let centre = &scene.geometry().instances()[8].placement;
    assert!(centre.mirrors());
    assert!((centre.to_world().matrix3.determinant() + 0.512).abs() < 1e-12);
}
