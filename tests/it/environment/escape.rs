//! Escaping rays see the environment, oriented as Mitsuba 3's envmap, in every scene format,
//! and the environment lights surfaces as ambient light (its diffuse irradiance).

use super::{quarters, rgbe_round, write_hdr};
use crate::common::exr::{channel, read_exr};
use crate::exr_passes::{H, W, at, lumis, ok};

/// A camera at the origin looking along +Z at nothing: the left half of the image looks
/// towards +X (u just below 0.5: green), the right half towards -X (just above: blue).
const EMPTY_TOML: &str = r#"
[render]
spp = 1
[camera]
position = [0.0, 0.0, 0.0]
look_at = [0.0, 0.0, 1.0]
fov = 60.0
[[sphere]]
center = [0.0, -1000.0, 0.0]
radius = 1.0
"#;

fn rgb(image: &crate::common::exr::FlatImage, i: usize) -> [f32; 3] {
    ["R", "G", "B"].map(|c| channel(image, c)[i])
}

#[test]
fn camera_rays_see_the_map_in_mitsubas_orientation_and_rotation_turns_it() {
    let dir = tempfile::tempdir().unwrap();
    write_hdr(&dir.path().join("sky.hdr"), 64, 32, quarters);
    std::fs::write(dir.path().join("s.toml"), EMPTY_TOML).unwrap();
    let [_, green, blue, white] = [0.0, 0.25, 0.5, 0.75].map(|u| rgbe_round(quarters(u, 0.5)));
    for (rotation, left, right) in [("0", green, blue), ("90", blue, white)] {
        ok(lumis(dir.path())
            .args(["s.toml", "-o", "o.exr", "--float", "--quiet"])
            .args(["--width", "32", "--height", "24", "--env", "sky.hdr"])
            .args(["--env-rotation", rotation])
            .output()
            .unwrap());
        let image = read_exr(&dir.path().join("o.exr"));
        assert_eq!(rgb(&image, at(4, 12)), left, "rotation {rotation}, left");
        assert_eq!(
            rgb(&image, at(W - 5, 12)),
            right,
            "rotation {rotation}, right"
        );
        assert_eq!(channel(&image, "A")[at(4, 12)], 1.0);
    }
}

#[test]
fn every_format_takes_the_environment_from_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let white = |_: f32, _: f32| [0.5, 0.5, 0.5];
    write_hdr(&d.join("sky.hdr"), 16, 8, white);
    // A tiny triangle far below the camera in each format: the frame is all environment.
    std::fs::write(
        d.join("m.obj"),
        "v 0 -100 0\nv 1 -100 0\nv 0 -100 1\nf 1 2 3\n",
    )
    .unwrap();
    let root = crate::common::files::root();
    let files = [
        d.join("m.obj"),
        root.join("tests/fixtures/scn/every_keyword.scn"),
        root.join("assets/gltf/cube.glb"),
    ];
    for file in &files {
        for how in [
            vec!["--env".to_string(), "sky.hdr".to_string()],
            vec![
                "-D".to_string(),
                format!("environment.file={:?}", d.join("sky.hdr").to_str().unwrap()),
            ],
        ] {
            ok(lumis(d)
                .arg(file)
                .args(["-o", "o.exr", "--float", "--quiet"])
                .args([
                    "--width",
                    "8",
                    "--height",
                    "6",
                    "--max-depth",
                    "0",
                    "--exposure",
                    "0",
                ])
                .args(&how)
                .output()
                .unwrap());
            let image = read_exr(&d.join("o.exr"));
            let a = channel(&image, "A");
            let ids = channel(&image, "id.object");
            let misses = (0..a.len()).filter(|&i| ids[i] < 0.0).count();
            assert!(misses > 0, "{file:?}: no pixel shows the environment");
            // Pixels whose centre ray missed but whose edge samples hit the model mix the
            // two: at least half the misses show exactly the map's grey.
            let r = channel(&image, "R");
            let grey = (0..a.len())
                .filter(|&i| ids[i] < 0.0 && a[i] == 1.0 && (r[i] - 0.5).abs() < 0.01)
                .count();
            assert!(
                grey * 2 >= misses,
                "{file:?} {how:?}: {grey} of {misses} misses show the map's 0.5"
            );
        }
    }
}

#[test]
fn a_uniform_environment_lights_a_white_sphere_to_its_own_radiance() {
    // Under a uniform sky of radiance L a Lambertian surface of albedo kd reflects kd L
    // (E = pi L): the ambient term is the environment's irradiance over pi.
    let dir = tempfile::tempdir().unwrap();
    let l = 0.75f32;
    write_hdr(&dir.path().join("sky.hdr"), 64, 32, |_, _| [l, l, l]);
    let scene = r#"
[render]
spp = 1
ambient = [0.3, 0.3, 0.3]   # replaced by the environment's
[camera]
position = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
fov = 40.0
[materials.white]
diffuse = [0.8, 0.6, 0.4]
[[sphere]]
center = [0.0, 0.0, 0.0]
radius = 1.0
material = "white"
[environment]
file = "sky.hdr"
"#;
    let image = crate::exr_passes::render(dir.path(), "s.toml", scene, "o.exr", &[]);
    let got = rgb(&image, at(W / 2, H / 2));
    let l = rgbe_round([l, l, l])[0];
    for (g, kd) in got.iter().zip([0.8, 0.6, 0.4]) {
        assert!((g / (kd * l) - 1.0).abs() < 0.01, "{got:?} vs kd x {l}");
    }
}
