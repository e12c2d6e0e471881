//! The query domain at every entry that makes rays (issue 24, `src/scene/domain.rs`): camera
//! values outside their ranges are refused in every scene format, through `-D` and through
//! animation keys, naming the file, the element and the range, exit 1, nothing written; rays of
//! any finite origin are answered, also through `lumis hits`, and far ones exactly.

use crate::common;
use crate::npy_rays::write_rays;

use common::hostile::gltf_with;
use std::path::Path;
use std::process::{Command, Output};

/// A unit sphere (primitive 0) in front of a camera, as TOML, with `camera` extra lines.
fn toml_scene(camera: &str) -> String {
    format!(
        "[render]\nwidth = 8\nheight = 8\n\n[camera]\nposition = [0.0, 0.0, 5.0]\n\
         look_at = [0.0, 0.0, 0.0]\n{camera}\n\n[materials.m]\ndiffuse = [0.5, 0.5, 0.5]\n\n\
         [[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = \"m\"\n"
    )
}

fn lumis(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lumis"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

/// Runs `lumis render FILE -o x.exr ARGS` on `file` written with `content`; asserts exit 1,
/// no output and no panic, and returns stderr.
fn refusal(dir: &Path, file: &str, content: &str, args: &[&str]) -> String {
    std::fs::write(dir.join(file), content).unwrap();
    let mut all = vec!["render", file, "-o", "x.exr", "-q"];
    all.extend(args);
    let out = lumis(dir, &all);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!dir.join("x.exr").exists(), "{stderr}");
    stderr
}

#[test]
fn camera_values_outside_the_domain_are_refused_with_the_key_and_the_range() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let aperture = "scene.toml: camera: aperture 1e30 is outside the supported range [0, 1e18]";
    // The case: a huge aperture panicked in the wide BVH.
    let e = refusal(d, "scene.toml", &toml_scene("aperture = 1e30"), &[]);
    assert!(e.contains(aperture), "{e}");
    // The same through -D on a valid file, and every other camera value.
    let valid = toml_scene("fov = 40.0");
    for (define, want) in [
        ("camera.aperture=1e30", aperture),
        (
            "camera.fov=1e-9",
            "scene.toml: camera: field of view 1e-9 degrees is outside the supported range \
             [1e-7, 180)",
        ),
        (
            "camera.focus_distance=1e30",
            "scene.toml: camera: focus distance 1e30 is outside the supported range (0, 4e18]",
        ),
        (
            "camera.position=[1e19, 0.0, 0.0]",
            "scene.toml: camera: position [1e19, 0e0, 0e0] exceeds the coordinate limit",
        ),
    ] {
        let e = refusal(d, "scene.toml", &valid, &["-D", define]);
        assert!(e.contains(want), "-D {define}: {e}");
    }
    // An orthographic view 1e-3 high seen from 1e10: finer than the f64 image plane resolves.
    let ortho = toml_scene("type = \"orthographic\"\nheight = 1e-3")
        .replace("[0.0, 0.0, 5.0]", "[0.0, 0.0, 1e10]");
    let e = refusal(d, "scene.toml", &ortho, &[]);
    assert!(e.contains("camera: orthographic height 1e-3 is outside the supported range [1e1"));
    // An animation whose camera leaves the domain at one frame fails whatever frame is asked.
    let animated = format!(
        "{valid}\n[animation]\nframes = 4\n[[animation.camera]]\nframe = 0\naperture = 0.0\n\
         [[animation.camera]]\nframe = 3\naperture = 1e30\n"
    );
    let e = refusal(d, "scene.toml", &animated, &["--frame", "0"]);
    assert!(e.contains("aperture") && e.contains("[0, 1e18]"), "{e}");
}

#[test]
fn cameras_of_every_format_meet_the_same_domain() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The paper's square lens (`dispersion`) wider than the world.
    let scn = "dispersion 1e30\ncameraPosition 0 0 100\ncameraUp 0 1 0\ncameraLookAt 0 0 0\n\
               cameraScreenWidth 384\nlight 50 50 1000 0.9\n\
               sphere 0 0 0 30 ShinyColor 0.9 0.2 0.3 100 0.4 null\n";
    let e = refusal(d, "scene.scn", scn, &[]);
    assert!(
        e.contains("scene.scn") && e.contains("lens size 1e30 is outside the supported range"),
        "{e}"
    );
    // A glTF camera with a field of view of 1e-12 rad.
    let gltf = gltf_with(serde_json::json!({
        "cameras": [{"type": "perspective", "perspective": {"yfov": 1e-12, "znear": 0.1}}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.3, 0.3, 2.0]}],
        "scenes": [{"nodes": [0, 1]}],
    }));
    let e = refusal(d, "scene.gltf", &gltf, &[]);
    assert!(
        e.contains("scene.gltf") && e.contains("field of view") && e.contains("[1e-7, 180)"),
        "{e}"
    );
}

/// Runs `lumis hits` in `dir` with `args` (after `hits`), which must succeed, and returns the
/// rows of its `--out` file `out`.
fn hits_rows(dir: &Path, args: &[&str], out: &str) -> Vec<Vec<f32>> {
    let run = lumis(dir, &[&["hits"], args, &["--out", out]].concat());
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    read_rows(&dir.join(out))
}

fn read_rows(path: &Path) -> Vec<Vec<f32>> {
    let bytes = std::fs::read(path).unwrap();
    let npy = npyz::NpyFile::new(&bytes[..]).unwrap();
    let cols = npy.shape()[1] as usize;
    let data: Vec<f32> = npy.into_vec().unwrap();
    data.chunks(cols).map(<[f32]>::to_vec).collect()
}

#[test]
fn hits_answers_rays_from_any_finite_origin() {
    // The examples through the CLI: from (x, x, x) with direction exactly -origin the
    // unit sphere's front is hit at t = 1 with its normal towards the ray; aimed 1e-3 rad
    // beside the knot from ~1e30, every accelerator misses (brute force reported hits at
    // t ~ 4e29 from overflowed products).
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("scene.toml"), toml_scene("fov = 40.0")).unwrap();
    let mut rays = Vec::new();
    for x in [1e6f32, 1e8, 1e19, 1e30, 1e38] {
        rays.push([x, x, x, -x, -x, -x, 0.0, f32::INFINITY]);
        rays.push([-x, 0.5 * x, 0.0, x, -0.5 * x, 0.0, 0.0, f32::INFINITY]);
    }
    write_rays(&d.join("rays.npy"), &rays);
    for accel in ["brute", "bsp", "bsmp", "sah"] {
        let rows = hits_rows(
            d,
            &["scene.toml", "--rays", "rays.npy", "--accel", accel],
            "h.npy",
        );
        for (i, row) in rows.iter().enumerate() {
            let r = &rays[i];
            let o = (r[0] as f64).hypot(r[1] as f64).hypot(r[2] as f64);
            let exact = 1.0 - 1.0 / o;
            assert!(
                (row[0] as f64 - exact).abs() <= 2.0 * f32::EPSILON as f64,
                "{accel}: ray {i}: t {} for {exact}",
                row[0]
            );
            assert_eq!(row[1], 0.0, "{accel}: ray {i}: the sphere");
            let n = [row[5], row[6], row[7]];
            let facing = n[0] * r[3] + n[1] * r[4] + n[2] * r[5];
            assert!(facing < 0.0, "{accel}: ray {i} hit the back: normal {n:?}");
        }
    }
    // Any hit: the blocker's t on the caller's ray (front or back, 1 -+ 1/|o|).
    let rows = hits_rows(
        d,
        &["scene.toml", "--rays", "rays.npy", "--any-hit"],
        "a.npy",
    );
    for (i, row) in rows.iter().enumerate() {
        assert!(
            (row[0] - 1.0).abs() <= 2e-6,
            "any hit: ray {i}: t {}",
            row[0]
        );
    }
    let knot = common::files::root().join("assets/knot.obj");
    let mut rays = Vec::new();
    for (k, x) in [1e20f32, 1e25, 1e30, 3e38].into_iter().enumerate() {
        for j in 0..8 {
            let a = (k * 8 + j) as f32 * 0.7;
            let o = [x * a.cos(), x * a.sin(), 0.3 * x];
            // -o turned by 1e-3 rad about z: misses the knot (size ~2) by ~1e-3 x.
            let (s, c) = (1e-3f32.sin(), 1e-3f32.cos());
            rays.push([
                o[0],
                o[1],
                o[2],
                -(o[0] * c - o[1] * s),
                -(o[0] * s + o[1] * c),
                -o[2],
                0.0,
                f32::INFINITY,
            ]);
        }
    }
    write_rays(&d.join("far.npy"), &rays);
    for accel in ["brute", "bsp", "bsmp", "sah"] {
        let knot = knot.to_str().unwrap();
        let rows = hits_rows(d, &[knot, "--rays", "far.npy", "--accel", accel], "k.npy");
        assert_eq!(rows.len(), rays.len());
        for (i, row) in rows.iter().enumerate() {
            assert_eq!(row[0], f32::INFINITY, "{accel}: ray {i} hit {row:?}");
        }
    }
}
