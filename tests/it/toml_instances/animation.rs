//! `[[animation.instance]]` keys pose an instance at the frame `--frame` asks for.

use super::{error, hit, load_at, world};
use lumis_core::math::Vec3;

/// A ball instanced as `mover`, keyed from x = 0 at frame 0 to x = 4 at frame 10, and turned
/// 90 degrees about Z on the way (a ball does not show it; the key only has to be taken).
const SCENE: &str = r#"
[animation]
frames = 11

[[sphere]]
name = "ball"
center = [0.0, 0.0, 0.0]
radius = 0.5

[[instance]]
of = "ball"
name = "mover"
scale = [1.0, 2.0, 1.0]

[[animation.instance]]
name = "mover"
frame = 0
translate = [0.0, 0.0, 0.0]
rotate = [0.0, 0.0, 0.0]

[[animation.instance]]
name = "mover"
frame = 10
translate = [4.0, 0.0, 0.0]
rotate = [0.0, 0.0, 90.0]
"#;

/// The height of the top of the posed instance above `x` (none when the ray misses).
fn top_at(frame: u32, x: f32) -> Option<f32> {
    let w = world(load_at(SCENE, &[], Some(frame)).unwrap_or_else(|e| panic!("{e}")));
    let (i, name) = hit(&w, Vec3::new(x, 10.0, 0.0), Vec3::NEG_Y)?;
    assert_eq!((name.as_str(), i.instance), ("mover", Some(0)));
    Some(i.surface.p.y)
}

#[test]
fn frames_place_the_instance_where_the_keys_say() {
    // Frame 0: at the origin, stretched to a height of 1 above it.
    assert!((top_at(0, 0.0).unwrap() - 1.0).abs() < 1e-4);
    assert_eq!(top_at(0, 4.0), None);
    // Frame 10: at x = 4, turned so its long axis lies along X (half-height 0.5).
    assert_eq!(top_at(10, 0.0), None);
    assert!((top_at(10, 4.0).unwrap() - 0.5).abs() < 1e-4);
    // Frame 5: halfway, x = 2, turned 45 degrees.
    let top = top_at(5, 2.0).unwrap();
    assert!(top > 0.5 && top < 1.0, "{top}");
    assert_eq!(top_at(5, 0.0), None);
}

#[test]
fn a_define_of_a_keyed_instance_field_warns_that_the_keys_win() {
    let scene = load_at(SCENE, &["instance.mover.translate=[9, 0, 0]"], Some(0)).unwrap();
    let w = scene.warnings().join("\n");
    assert!(
        w.contains("-D instance.mover.translate=[9, 0, 0]: keys in [[animation.instance]]"),
        "{w}"
    );
    // A field no key gives is not shadowed: scale moves the instance's top.
    let scene = load_at(SCENE, &["instance.mover.scale=[1, 4, 1]"], Some(0)).unwrap();
    assert!(scene.warnings().is_empty(), "{:?}", scene.warnings());
    let (i, _) = hit(&world(scene), Vec3::new(0.0, 10.0, 0.0), Vec3::NEG_Y).unwrap();
    assert!((i.surface.p.y - 2.0).abs() < 1e-4, "{}", i.surface.p.y);
}

#[test]
fn instance_keys_are_checked_as_mesh_keys_are() {
    let with = |key: &str| format!("{SCENE}\n[[animation.instance]]\n{key}\n");
    let e = error(
        &with("name = \"ghost\"\nframe = 3\ntranslate = [0.0, 0.0, 0.0]"),
        &[],
    );
    assert!(
        e.contains("animation.instance[2] \"ghost\" (frame 3): no [[instance]] is named \"ghost\""),
        "{e}"
    );
    let e = error(
        &with("name = \"mover\"\nframe = 4\ntranslate = [nan, 0.0, 0.0]"),
        &[],
    );
    assert!(
        e.contains(
            "animation.instance[2] \"mover\" (frame 4): translate [NaN, 0.0, 0.0] must be finite"
        ),
        "{e}"
    );
    let e = error(&with("name = \"mover\"\nframe = 5"), &[]);
    assert!(e.contains("the key animates nothing"), "{e}");
    let e = error(
        &with("name = \"mover\"\nframe = 11\nrotate = [1.0, 0.0, 0.0]"),
        &[],
    );
    assert!(e.contains("frame 11 is outside the animation"), "{e}");
    // An instance of many placements has no single translate to key.
    let arrays = SCENE.replace(
        "scale = [1.0, 2.0, 1.0]",
        "translations = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]]",
    );
    let e = error(&arrays, &[]);
    assert!(
        e.contains(
            "animation.instance[0] \"mover\" (frame 0): the [[instance]] is placed by translations"
        ),
        "{e}"
    );
}
