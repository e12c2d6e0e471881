//! The render flags pbrt-v4 and Mitsuba 3 users expect, through the built binary, checked on
//! pixels and sizes: `-D`, `--samples`, `--exposure` in every format, `--tonemap`,
//! `--background`, `--threads` and `--quick`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use exr::prelude::{AttributeValue, Text};
use lumis_core::film::{Tonemap, linear_to_srgb8};

use crate::common;
use common::exr::{FlatImage, channel, read_exr};

/// A sphere filling the middle of a 16x16 image on a black background, lit by ambient only:
/// corners miss, the centre hits material `m` of sphere `ball`.
const BALL: &str = r#"
[render]
width = 16
height = 16
spp = 1
ambient = [0.5, 0.5, 0.5]

[camera]
position = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
fov = 30.0

[materials.m]
diffuse = [0.5, 0.5, 0.5]

[[sphere]]
name = "ball"
center = [0.0, 0.0, 0.0]
radius = 1.0
material = "m"
"#;

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// `lumis render` with `args` in `dir`.
fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lumis"))
        .current_dir(dir)
        .arg("render")
        .args(args)
        .output()
        .unwrap()
}

/// [`run`], which must succeed; returns its stderr.
fn ok(dir: &Path, args: &[&str]) -> String {
    let out = run(dir, args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{args:?}: {stderr}");
    stderr
}

/// [`run`], which must fail cleanly; returns its stderr.
fn fails(dir: &Path, args: &[&str]) -> String {
    let out = run(dir, args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "{args:?} succeeded");
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

fn ball(dir: &Path) -> String {
    let path = dir.join("ball.toml");
    std::fs::write(&path, BALL).unwrap();
    path.to_string_lossy().into_owned()
}

/// The RGB of pixel `i` of a `--float` EXR.
fn rgb(image: &FlatImage, i: usize) -> [f32; 3] {
    ["R", "G", "B"].map(|c| channel(image, c)[i])
}

fn spp_attr(image: &FlatImage) -> Option<AttributeValue> {
    let attrs = &image.layer_data[0].attributes.other;
    attrs.get(&Text::from(lumis_io::output::ATTR_SPP)).cloned()
}

fn png_size(path: &Path) -> (u32, u32) {
    let png = image::open(path).unwrap();
    (png.width(), png.height())
}

const CENTRE: usize = 8 * 16 + 8;

#[test]
fn defines_set_any_toml_key_later_wins_and_flags_win_over_them() {
    let dir = tempfile::tempdir().unwrap();
    let (d, scene) = (dir.path(), ball(dir.path()));
    let q = ["-q", "--float"];
    ok(
        d,
        &[
            &scene,
            "-o",
            "a.png",
            "-q",
            "-D",
            "render.width=30",
            "-D",
            "render.width=12",
        ],
    );
    assert_eq!(png_size(&d.join("a.png")), (12, 16));
    ok(
        d,
        &[
            &scene,
            "-o",
            "b.png",
            "-q",
            "-D",
            "render.width=30",
            "--width",
            "9",
        ],
    );
    assert_eq!(png_size(&d.join("b.png")), (9, 16));
    // A material key: the centre glows red.
    ok(
        d,
        &[
            &[&scene, "-o", "m.exr", "-D", "materials.m.emission=[2,0,0]"],
            &q[..],
        ]
        .concat(),
    );
    let [r, g, _] = rgb(&read_exr(&d.join("m.exr")), CENTRE);
    assert!(r > 2.0 && g < 0.5, "centre {r} {g}");
    // An array element by name, and one by index: a tiny ball lets the centre miss.
    for key in ["sphere.ball.radius=0.01", "sphere.0.radius=0.01"] {
        let args = ["-o", "s.exr", "-D", key, "-D", "render.background=[0,0,1]"];
        ok(d, &[&[scene.as_str()], &args[..], &q[..]].concat());
        assert_eq!(
            rgb(&read_exr(&d.join("s.exr")), CENTRE),
            [0.0, 0.0, 1.0],
            "{key}"
        );
    }
}

#[test]
fn bad_defines_fail_naming_the_key_and_what_was_expected() {
    let dir = tempfile::tempdir().unwrap();
    let (d, scene) = (dir.path(), ball(dir.path()));
    let knot = repo("assets/knot.obj");
    let knot = knot.to_str().unwrap();
    let cases: [(&[&str], &[&str]); 6] = [
        (&["-D", "render.spp=abc"], &["render.spp", "expected u32"]),
        (
            &["-D", "render.nope=1"],
            &["render.nope", "unknown field `nope`", "spp"],
        ),
        (&["-D", "camera.fov=[1]"], &["camera.fov", "expected f32"]),
        (
            &["-D", "sphere.3.radius=1"],
            &["sphere.3.radius", "no element 3"],
        ),
        (&["-D", "render.spp"], &["render.spp", "KEY=VALUE"]),
        (
            &[knot, "-D", "camera.fov=30"],
            &["camera.fov", "render.*", ".obj"],
        ),
    ];
    for (args, needles) in cases {
        let with_scene: Vec<&str> = if args[0] == knot {
            args.to_vec()
        } else {
            [&[scene.as_str()], args].concat()
        };
        let stderr = fails(d, &[&with_scene[..], &["-o", "x.png", "-q"]].concat());
        for n in needles {
            assert!(stderr.contains(n), "{args:?}: no {n:?} in {stderr}");
        }
    }
    // The value checks of the file apply too.
    let stderr = fails(d, &[&scene, "-D", "render.spp=0", "-o", "x.png"]);
    assert!(stderr.contains("spp 0 must be in 1..=64"), "{stderr}");
    assert!(!d.join("x.png").exists());
}

#[test]
fn other_formats_take_render_keys_through_the_same_schema() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for file in ["assets/knot.obj", "tests/fixtures/scn/every_keyword.scn"] {
        let f = repo(file);
        let size = [
            "-D",
            "render.width=8",
            "-D",
            "render.height=4",
            "-o",
            "o.png",
            "-q",
        ];
        ok(d, &[&[f.to_str().unwrap()], &size[..]].concat());
        assert_eq!(png_size(&d.join("o.png")), (8, 4), "{file}");
        let stderr = fails(d, &[f.to_str().unwrap(), "-D", "render.width=wide", "-q"]);
        assert!(
            stderr.contains("render.width") && stderr.contains("expected u32"),
            "{stderr}"
        );
    }
}

#[test]
fn samples_is_a_total_rounded_to_a_square_and_conflicts_with_spp() {
    let dir = tempfile::tempdir().unwrap();
    let (d, scene) = (dir.path(), ball(dir.path()));
    let stderr = ok(d, &[&scene, "--samples", "10", "-o", "a.exr"]);
    assert!(stderr.contains("--samples 10: using 9 (3x3)"), "{stderr}");
    assert_eq!(
        spp_attr(&read_exr(&d.join("a.exr"))),
        Some(AttributeValue::I32(9))
    );
    let stderr = ok(d, &[&scene, "--samples", "16", "-o", "b.exr"]);
    assert!(!stderr.contains("using"), "16 is a square: {stderr}");
    assert_eq!(
        spp_attr(&read_exr(&d.join("b.exr"))),
        Some(AttributeValue::I32(16))
    );
    let stderr = fails(d, &[&scene, "--samples", "4", "--spp", "2"]);
    assert!(stderr.contains("cannot be used with"), "{stderr}");
}

#[test]
fn exposure_scales_the_exr_of_every_format_by_a_power_of_two() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scn = repo("tests/fixtures/scn/every_keyword.scn");
    let obj = repo("assets/knot.obj");
    // No scene: the built-in TOML scene.
    for scene in [None, Some(&obj), Some(&scn)] {
        let mut images = Vec::new();
        for ev in ["0", "1"] {
            let mut args: Vec<&str> = scene.map(|s| s.to_str().unwrap()).into_iter().collect();
            args.extend([
                "--width", "16", "--height", "12", "--spp", "1", "--float", "-q",
            ]);
            args.extend(["--exposure", ev, "-o", "e.exr"]);
            ok(d, &args);
            images.push(channel(&read_exr(&d.join("e.exr")), "G"));
        }
        assert!(images[0].iter().any(|&v| v > 0.0), "{scene:?} is black");
        for (a, b) in images[0].iter().zip(&images[1]) {
            assert_eq!(a * 2.0, *b, "{scene:?}");
        }
    }
}

#[test]
fn filmic_tonemap_shapes_the_png_only() {
    let dir = tempfile::tempdir().unwrap();
    let (d, scene) = (dir.path(), ball(dir.path()));
    let glow = ["-D", "materials.m.emission=[4,1,0.25]", "--float", "-q"];
    ok(
        d,
        &[
            &[
                scene.as_str(),
                "-o",
                "t.exr",
                "--png",
                "t.png",
                "--tonemap",
                "filmic",
            ],
            &glow[..],
        ]
        .concat(),
    );
    ok(
        d,
        &[
            &[scene.as_str(), "-o", "n.exr", "--png", "n.png"],
            &glow[..],
        ]
        .concat(),
    );
    let (exr, plain) = (read_exr(&d.join("t.exr")), read_exr(&d.join("n.exr")));
    // The EXR stays linear: the same with and without the curve.
    assert_eq!(channel(&exr, "R"), channel(&plain, "R"));
    let png = image::open(d.join("t.png")).unwrap().to_rgb8();
    for (i, p) in png.pixels().enumerate() {
        let expected = rgb(&exr, i).map(|v| linear_to_srgb8(Tonemap::Filmic.apply(v)));
        assert_eq!(p.0, expected, "pixel {i}");
    }
    // Without the curve the bright red centre clips; with it, it stays below white.
    let none = image::open(d.join("n.png")).unwrap().to_rgb8();
    let c = (8, 8);
    assert_eq!(none.get_pixel(c.0, c.1).0[0], 255);
    assert!(png.get_pixel(c.0, c.1).0[0] < 255);
}

#[test]
fn background_overrides_the_scene_in_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let (d, scene) = (dir.path(), ball(dir.path()));
    let obj = repo("assets/knot.obj");
    let bg = [
        "--background",
        "0.25,0.5,1",
        "--float",
        "-q",
        "--exposure",
        "0",
        "-o",
        "b.exr",
    ];
    for file in [scene.as_str(), obj.to_str().unwrap()] {
        // --background wins over -D render.background, which wins over the file.
        ok(
            d,
            &[&[file, "-D", "render.background=[1,0,0]"], &bg[..]].concat(),
        );
        let image = read_exr(&d.join("b.exr"));
        assert_eq!(rgb(&image, 0), [0.25, 0.5, 1.0], "{file}: corner");
    }
    let stderr = fails(d, &[&scene, "--background", "1,2"]);
    assert!(stderr.contains("R,G,B"), "{stderr}");
}

#[test]
fn threads_zero_is_all_cores_and_absurd_counts_are_capped() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let base = [
        "--width", "24", "--height", "16", "--spp", "1", "--seed", "3",
    ];
    let mut pngs = Vec::new();
    for (threads, name) in [("1", "a.png"), ("0", "b.png"), ("100000", "c.png")] {
        let stderr = ok(
            d,
            &[&base[..], &["--threads", threads, "-o", name]].concat(),
        );
        let capped = stderr.contains("--threads 100000: capped at");
        assert_eq!(capped, threads == "100000", "{stderr}");
        pngs.push(std::fs::read(d.join(name)).unwrap());
    }
    assert!(
        pngs[0] == pngs[1] && pngs[1] == pngs[2],
        "images differ by thread count"
    );
}

#[test]
fn quick_quarters_each_side_and_renders_one_sample() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The default scene is 640x360 at 2x2 samples.
    let stderr = ok(d, &["--quick", "-o", "q.exr", "--png", "q.png"]);
    assert!(stderr.contains("--quick: 160x90"), "{stderr}");
    assert_eq!(png_size(&d.join("q.png")), (160, 90));
    assert_eq!(
        spp_attr(&read_exr(&d.join("q.exr"))),
        Some(AttributeValue::I32(1))
    );
    // Applied after the other flags, and never below one pixel.
    ok(
        d,
        &[
            "--quick", "--width", "6", "--height", "3", "-o", "t.png", "-q",
        ],
    );
    assert_eq!(png_size(&d.join("t.png")), (1, 1));
}
