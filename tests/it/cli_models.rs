//! Model files through the built binary: `--exposure` (exact powers of two in the EXR),
//! automatic exposure for photometric lights, `--up z` and `--auto-camera`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use exr::prelude::{AttributeValue, Text};

use crate::common;
use common::exr::{FlatImage, channel, read_exr};

fn asset(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/gltf")
        .join(name)
}

/// `lumis render SCENE -o OUT --quiet` plus `extra`, in `dir`; panics unless it succeeds.
fn render(dir: &Path, scene: &Path, out: &str, extra: &[&str]) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_lumis"))
        .current_dir(dir)
        .arg("render")
        .arg(scene)
        .args(["-o", out, "--spp", "1", "--threads", "2"])
        .args(extra)
        .output()
        .unwrap();
    common::cli::assert_ok(&out);
    out
}

fn exposure_attr(image: &FlatImage) -> Option<AttributeValue> {
    let attrs = &image.layer_data[0].attributes;
    attrs
        .other
        .get(&Text::from(lumis_io::output::ATTR_EXPOSURE))
        .cloned()
}

#[test]
fn exposure_one_doubles_linear_exr_values_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let size = ["--width", "32", "--height", "24", "--float", "--quiet"];
    let cube = asset("lights_camera.gltf");
    render(
        dir.path(),
        &cube,
        "a.exr",
        &[&size[..], &["--exposure", "0"]].concat(),
    );
    render(
        dir.path(),
        &cube,
        "b.exr",
        &[&size[..], &["--exposure", "1"]].concat(),
    );
    let (a, b) = (
        read_exr(&dir.path().join("a.exr")),
        read_exr(&dir.path().join("b.exr")),
    );
    for c in ["R", "G", "B"] {
        let (va, vb) = (channel(&a, c), channel(&b, c));
        assert!(va.iter().any(|v| *v > 0.0), "{c} is black");
        for (x, y) in va.iter().zip(&vb) {
            assert_eq!((2.0 * x).to_bits(), y.to_bits(), "{c}: {x} -> {y}");
        }
    }
    assert_eq!(channel(&a, "A"), channel(&b, "A"), "alpha is not exposed");
    assert_eq!(channel(&a, "Z"), channel(&b, "Z"), "depth is not exposed");
    assert_eq!(exposure_attr(&b), Some(AttributeValue::F32(1.0)));
}

#[test]
fn a_68300_lux_sun_is_auto_exposed_into_range() {
    let dir = tempfile::tempdir().unwrap();
    let sun = asset("sun.gltf");
    let size = ["--width", "48", "--height", "32"];
    let out = render(dir.path(), &sun, "auto.exr", &size);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("auto exposure: -"), "{stderr}");
    render(
        dir.path(),
        &sun,
        "auto.png",
        &[&size[..], &["--quiet"]].concat(),
    );
    render(
        dir.path(),
        &sun,
        "raw.png",
        &[&size[..], &["--quiet", "--exposure", "0"]].concat(),
    );
    let ev = match exposure_attr(&read_exr(&dir.path().join("auto.exr"))) {
        Some(AttributeValue::F32(ev)) => ev,
        other => panic!("{other:?}"),
    };
    assert!(ev < -2.0, "{ev}");
    // Channels at 255 among the pixels the model covers (the background is black).
    let clipped = |name: &str| {
        let png = image::open(dir.path().join(name)).unwrap().to_rgb8();
        let lit: Vec<_> = png.pixels().filter(|p| p.0 != [0, 0, 0]).collect();
        let white = lit.iter().filter(|p| p.0.iter().all(|c| *c == 255)).count();
        (white as f32 / lit.len() as f32, lit.len())
    };
    let (raw, _) = clipped("raw.png");
    let (auto, lit) = clipped("auto.png");
    assert!(
        raw > 0.5,
        "without exposure the sun should blow the image out ({raw})"
    );
    assert!(
        lit > 100 && auto < 0.05,
        "auto exposure leaves {auto} of {lit} pixels white"
    );
}

/// Rows and columns spanned by non-black pixels of a PNG.
fn extent(png: &Path) -> (u32, u32) {
    let img = image::open(png).unwrap().to_rgb8();
    let (mut x0, mut x1, mut y0, mut y1) = (u32::MAX, 0, u32::MAX, 0);
    for (x, y, p) in img.enumerate_pixels() {
        if p.0 != [0, 0, 0] {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
    }
    (x1 + 1 - x0, y1 + 1 - y0)
}

#[test]
fn up_z_stands_a_z_up_model_upright() {
    let dir = tempfile::tempdir().unwrap();
    // A post 0.2 x 0.2 wide and 2 tall along +Z.
    let mut obj = String::new();
    for z in [0.0, 2.0] {
        for (x, y) in [(-0.1, -0.1), (0.1, -0.1), (0.1, 0.1), (-0.1, 0.1)] {
            obj += &format!("v {x} {y} {z}\n");
        }
    }
    obj += "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    let post = dir.path().join("post.obj");
    std::fs::write(&post, obj).unwrap();
    let size = ["--width", "64", "--height", "64", "--quiet"];
    render(dir.path(), &post, "lying.png", &size);
    render(
        dir.path(),
        &post,
        "upright.png",
        &[&size[..], &["--up", "z"]].concat(),
    );
    let (w, h) = extent(&dir.path().join("upright.png"));
    assert!(h > 3 * w, "upright post spans {w} x {h} pixels");
    let (w, h) = extent(&dir.path().join("lying.png"));
    assert!(w > h, "lying post spans {w} x {h} pixels");
}

/// The view direction in an EXR's `worldToCamera` (Imath row-major, row vectors: the third
/// column holds the forward axis).
fn forward(exr: &Path) -> [f32; 3] {
    let image = read_exr(exr);
    let m = image.layer_data[0]
        .attributes
        .world_to_camera
        .expect("worldToCamera");
    [m[2], m[6], m[10]]
}

#[test]
fn auto_camera_replaces_the_file_camera() {
    let dir = tempfile::tempdir().unwrap();
    let scene = asset("lights_camera.gltf");
    let size = ["--width", "24", "--height", "16", "--quiet"];
    render(dir.path(), &scene, "file.exr", &size);
    render(
        dir.path(),
        &scene,
        "auto.exr",
        &[&size[..], &["--auto-camera"]].concat(),
    );
    let f = forward(&dir.path().join("file.exr"));
    assert!(f[2] < -0.999, "the file camera looks down -Z: {f:?}");
    // The framing camera looks from the front-right-above.
    let a = forward(&dir.path().join("auto.exr"));
    assert!(a[0] < -0.2 && a[1] < -0.1 && a[2] < -0.5, "{a:?}");
}

#[test]
fn model_flags_are_refused_where_they_do_not_apply() {
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_lumis"))
            .current_dir(dir.path())
            .arg("render")
            .args(args)
            .args(["-o", "x.png", "--quiet"])
            .output()
            .unwrap()
    };
    let toml = dir.path().join("s.toml");
    std::fs::write(
        &toml,
        "[camera]\nposition = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n",
    )
    .unwrap();
    let scene = asset("lights_camera.gltf");
    let scene = scene.to_str().unwrap();
    for args in [
        vec![toml.to_str().unwrap(), "--up", "z"],
        vec![toml.to_str().unwrap(), "--auto-camera"],
        vec!["--up", "z"],
        vec![scene, "--auto-camera", "--camera", "0"],
        vec![scene, "--exposure", "nan"],
        vec![scene, "--up", "x"],
    ] {
        let out = run(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && !stderr.contains("panicked"),
            "{args:?}: {stderr}"
        );
        assert!(!dir.path().join("x.png").exists(), "{args:?}");
    }
}
