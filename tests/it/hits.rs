//! `lumis hits`: known answers on a unit sphere and a quad, misses, any-hit, bad input,
//! `--triangles-out`, and thread-count independence.

use crate::npy_rays::write_rays;
use npyz::WriterBuilder;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A unit sphere at the origin (primitive 0, object 0) and a quad in z = -5 spanning
/// x in [2, 4], y in [-1, 1], wound counter-clockwise seen from +z (primitives 1 and 2,
/// object 1).
const SCENE: &str = "[camera]
position = [0.0, 0.0, 10.0]
look_at = [0.0, 0.0, 0.0]

[materials.m]
diffuse = [0.5, 0.5, 0.5]

[[sphere]]
name = \"ball\"
center = [0.0, 0.0, 0.0]
radius = 1.0
material = \"m\"

[[mesh]]
name = \"quad\"
material = \"m\"
positions = [[2.0, -1.0, -5.0], [4.0, -1.0, -5.0], [4.0, 1.0, -5.0], [2.0, 1.0, -5.0]]
indices = [[0, 1, 2], [0, 2, 3]]
";

const INF: f32 = f32::INFINITY;

fn setup() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, SCENE).unwrap();
    (dir, scene)
}

fn write_npy<T: npyz::Serialize + npyz::AutoSerialize + Copy>(
    path: &Path,
    shape: &[u64],
    data: &[T],
) {
    let mut bytes = Vec::new();
    let mut w = npyz::WriteOptions::<T>::new()
        .default_dtype()
        .shape(shape)
        .writer(&mut bytes)
        .begin_nd()
        .unwrap();
    w.extend(data.iter().copied()).unwrap();
    w.finish().unwrap();
    std::fs::write(path, bytes).unwrap();
}

/// Reads a float32 2-D array: (shape, rows).
fn read_f32(path: &Path) -> (Vec<u64>, Vec<Vec<f32>>) {
    let bytes = std::fs::read(path).unwrap();
    let npy = npyz::NpyFile::new(&bytes[..]).unwrap();
    let shape = npy.shape().to_vec();
    let flat: Vec<f32> = npy.into_vec().unwrap();
    let rows = flat
        .chunks(shape[1] as usize)
        .map(<[f32]>::to_vec)
        .collect();
    (shape, rows)
}

fn lumis(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lumis"))
        .arg("hits")
        .args(args)
        .output()
        .unwrap()
}

fn run_hits(scene: &Path, rays: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        scene.as_os_str(),
        "--rays".as_ref(),
        rays.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ];
    args.extend(extra.iter().map(std::ffi::OsStr::new));
    lumis(&args)
}

fn assert_ok(o: &Output) {
    assert!(
        o.status.success(),
        "lumis hits failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Rays with analytic answers, and the closest-hit row each should give.
fn known_rays() -> Vec<([f32; 8], [f32; 9])> {
    vec![
        // Straight down onto the sphere's top: t = 4, outward normal +z.
        (
            [0., 0., 5., 0., 0., -1., 0., INF],
            [4., 0., 0., 0., 0., 0., 0., 1., 0.],
        ),
        // A direction of length 2 measures t in its own units.
        (
            [0., 0., 5., 0., 0., -2., 0., INF],
            [2., 0., 0., 0., 0., 0., 0., 1., 0.],
        ),
        // From inside the sphere: the exit point, normal still outward.
        (
            [0., 0., 0., 1., 0., 0., 0., INF],
            [1., 0., 0., 0., 0., 1., 0., 0., 0.],
        ),
        // First quad triangle (v0, v1, v2) at (3.5, -0.5): u = 0.5, v = 0.25.
        (
            [3.5, -0.5, 0., 0., 0., -1., 0., INF],
            [5., 1., 1., 0.5, 0.25, 0., 0., 1., 1.],
        ),
        // Second quad triangle (v0, v2, v3) at (2.5, 0.5): u = 0.25, v = 0.5.
        (
            [2.5, 0.5, 0., 0., 0., -1., 0., INF],
            [5., 2., 1., 0.25, 0.5, 0., 0., 1., 1.],
        ),
        // Pointing away from everything: a miss.
        (
            [0., 0., 5., 0., 0., 1., 0., INF],
            [INF, -1., -1., 0., 0., 0., 0., 0., -1.],
        ),
        // t_max stops short of the sphere: a miss.
        (
            [0., 0., 5., 0., 0., -1., 0., 3.],
            [INF, -1., -1., 0., 0., 0., 0., 0., -1.],
        ),
        // t_min past the sphere's far side; the quad is not on this line: a miss.
        (
            [0., 0., 5., 0., 0., -1., 6.5, INF],
            [INF, -1., -1., 0., 0., 0., 0., 0., -1.],
        ),
    ]
}

fn assert_row(got: &[f32], want: &[f32; 9], ray: usize) {
    // t and the ids are exact; barycentrics and normals within 1e-6.
    assert_eq!(got[..3], want[..3], "ray {ray}: t and ids, row {got:?}");
    assert_eq!(got[8], want[8], "ray {ray}: kind, row {got:?}");
    for c in 3..8 {
        assert!(
            (got[c] - want[c]).abs() <= 1e-6,
            "ray {ray}: column {c} is {} not {}",
            got[c],
            want[c]
        );
    }
}

#[test]
fn closest_hits_match_analytic_answers_for_every_accel() {
    let (dir, scene) = setup();
    let cases = known_rays();
    let rays: Vec<[f32; 8]> = cases.iter().map(|c| c.0).collect();
    let rays_path = dir.path().join("rays.npy");
    write_rays(&rays_path, &rays);
    let builds = [("brute", "full"), ("bsp", "full"), ("bsmp", "full")];
    for (accel, build) in builds.into_iter().chain([("sah", "full"), ("sah", "fast")]) {
        for traversal in ["ordered", "segments", "exhaustive"] {
            let out = dir
                .path()
                .join(format!("hits_{accel}_{build}_{traversal}.npy"));
            let o = run_hits(
                &scene,
                &rays_path,
                &out,
                &["--accel", accel, "--build", build, "--traversal", traversal],
            );
            assert_ok(&o);
            let (shape, rows) = read_f32(&out);
            assert_eq!(shape, [cases.len() as u64, 9]);
            for (i, (row, (_, want))) in rows.iter().zip(&cases).enumerate() {
                assert_row(row, want, i);
            }
        }
    }
}

#[test]
fn any_hit_reports_blocker_t_or_infinity_and_no_ids() {
    let (dir, scene) = setup();
    let cases = known_rays();
    let rays: Vec<[f32; 8]> = cases.iter().map(|c| c.0).collect();
    let rays_path = dir.path().join("rays.npy");
    write_rays(&rays_path, &rays);
    let out = dir.path().join("any.npy");
    assert_ok(&run_hits(&scene, &rays_path, &out, &["--any-hit"]));
    let (shape, rows) = read_f32(&out);
    assert_eq!(shape, [cases.len() as u64, 9]);
    for (i, (row, (_, want))) in rows.iter().zip(&cases).enumerate() {
        // Each of these rays meets at most one surface, so the blocker is the closest hit.
        let expect = [want[0], -1., -1., 0., 0., 0., 0., 0., -1.];
        assert_eq!(row[..], expect, "ray {i}");
    }
}

#[test]
fn triangles_out_lists_the_quad_in_world_space() {
    let (dir, scene) = setup();
    let rays_path = dir.path().join("rays.npy");
    write_rays(&rays_path, &[known_rays()[0].0]);
    let out = dir.path().join("hits.npy");
    let tris = dir.path().join("tris.npy");
    let o = run_hits(
        &scene,
        &rays_path,
        &out,
        &["--triangles-out", tris.to_str().unwrap()],
    );
    assert_ok(&o);
    let (shape, rows) = read_f32(&tris);
    assert_eq!(shape, [2, 10]);
    assert_eq!(
        rows[0],
        [1., 2., -1., -5., 4., -1., -5., 4., 1., -5.],
        "first triangle"
    );
    assert_eq!(
        rows[1],
        [2., 2., -1., -5., 4., 1., -5., 2., 1., -5.],
        "second triangle"
    );
}

#[test]
fn spheres_out_lists_the_ball_with_its_primitive_id() {
    let (dir, scene) = setup();
    let rays_path = dir.path().join("rays.npy");
    write_rays(&rays_path, &[known_rays()[0].0]);
    let out = dir.path().join("hits.npy");
    let spheres = dir.path().join("spheres.npy");
    let o = run_hits(
        &scene,
        &rays_path,
        &out,
        &["--spheres-out", spheres.to_str().unwrap()],
    );
    assert_ok(&o);
    let (shape, rows) = read_f32(&spheres);
    assert_eq!(shape, [1, 5]);
    assert_eq!(rows[0], [0., 0., 0., 0., 1.]);
}

#[test]
fn repeat_and_rebuild_run_again_and_timings_list_each_run() {
    let (dir, scene) = setup();
    let rays_path = dir.path().join("rays.npy");
    let cases = known_rays();
    let rays: Vec<[f32; 8]> = cases.iter().map(|c| c.0).collect();
    write_rays(&rays_path, &rays);
    let once = dir.path().join("once.npy");
    assert_ok(&run_hits(&scene, &rays_path, &once, &[]));
    let thrice = dir.path().join("thrice.npy");
    let timings = dir.path().join("t.json");
    let t = timings.to_str().unwrap();
    assert_ok(&run_hits(
        &scene,
        &rays_path,
        &thrice,
        &["--repeat", "3", "--rebuild", "2", "--timings", t],
    ));
    assert_eq!(
        read_f32(&once),
        read_f32(&thrice),
        "repeating changes nothing"
    );
    let json = std::fs::read_to_string(&timings).unwrap();
    let parsed: serde_json::Value = serde_json::from_str(&json).expect("timings are JSON");
    assert_eq!(parsed["rays"], rays.len(), "{json}");
    let runs: Vec<f64> = parsed["trace_s"]
        .as_array()
        .expect("trace_s is a list")
        .iter()
        .map(|s| s.as_f64().expect("seconds"))
        .collect();
    for key in ["prims", "geometry_bytes", "accel_bytes"] {
        assert!(parsed[key].as_u64().is_some_and(|n| n > 0), "{key}: {json}");
    }
    let parts = ["nodes", "leaf_order", "packed"].map(|k| {
        parsed["accel_parts"][k]
            .as_u64()
            .unwrap_or_else(|| panic!("accel_parts.{k}: {json}"))
    });
    assert!(parts.iter().all(|&n| n > 0), "{json}");
    assert_eq!(
        parts.iter().sum::<u64>(),
        parsed["accel_bytes"].as_u64().unwrap(),
        "the parts make up the whole: {json}"
    );
    assert_eq!(runs.len(), 3, "{json}");
    assert!(runs.iter().all(|&s| s >= 0.0 && s.is_finite()), "{json}");
    let builds = parsed["build_runs_s"]
        .as_array()
        .expect("build_runs_s is a list");
    assert_eq!(builds.len(), 2, "{json}");
    assert_eq!(builds[0], parsed["build_s"], "{json}");
    assert!(
        parsed["sah_cost"].as_f64().is_some_and(|c| c >= 1.0),
        "{json}"
    );
    let o = run_hits(&scene, &rays_path, &thrice, &["--repeat", "0"]);
    assert!(!o.status.success(), "--repeat 0 must be refused");
    let o = run_hits(&scene, &rays_path, &thrice, &["--rebuild", "0"]);
    assert!(!o.status.success(), "--rebuild 0 must be refused");
}

#[test]
fn output_is_identical_for_one_and_two_threads() {
    let (dir, scene) = setup();
    // A fan of 5000 rays from a fixed point, covering sphere, quad and empty space.
    let rays: Vec<[f32; 8]> = (0..5000)
        .map(|i| {
            let a = i as f32 * 0.37;
            let b = (i % 97) as f32 / 97.0 - 0.5;
            [0.5, 0.2, 6.0, a.cos() * 0.3 + 0.1, b * 0.4, -1.0, 0.0, INF]
        })
        .collect();
    let rays_path = dir.path().join("rays.npy");
    write_rays(&rays_path, &rays);
    for any in [false, true] {
        let outputs: Vec<Vec<u8>> = ["1", "2"]
            .iter()
            .map(|n| {
                let out = dir.path().join(format!("hits_{n}.npy"));
                let mut extra = vec!["--threads", n];
                if any {
                    extra.push("--any-hit");
                }
                assert_ok(&run_hits(&scene, &rays_path, &out, &extra));
                std::fs::read(&out).unwrap()
            })
            .collect();
        assert_eq!(outputs[0], outputs[1], "any-hit {any}");
        let (_, rows) = read_f32(&dir.path().join("hits_1.npy"));
        assert!(rows.iter().any(|r| r[0].is_finite()), "some rays hit");
        assert!(rows.iter().any(|r| r[0].is_infinite()), "some rays miss");
    }
}

/// Runs `lumis hits` on a bad rays file; asserts failure naming the file and no output.
fn assert_rejected(dir: &Path, scene: &Path, rays: &Path, expect: &str) {
    let out = dir.join("never.npy");
    let o = run_hits(scene, rays, &out, &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{} was accepted", rays.display());
    assert!(
        err.contains(rays.file_name().unwrap().to_str().unwrap()),
        "error does not name the file: {err}"
    );
    assert!(err.contains(expect), "error lacks {expect:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(!out.exists(), "output written for bad input");
}

#[test]
fn bad_ray_files_fail_naming_the_file_and_write_nothing() {
    let (dir, scene) = setup();
    let d = dir.path();

    let wrong_shape = d.join("wrong_shape.npy");
    write_npy(&wrong_shape, &[3, 7], &[0f32; 21]);
    assert_rejected(d, &scene, &wrong_shape, "expected (N, 8)");

    let one_d = d.join("one_d.npy");
    write_npy(&one_d, &[8], &[0f32; 8]);
    assert_rejected(d, &scene, &one_d, "expected (N, 8)");

    let float64 = d.join("float64.npy");
    write_npy(&float64, &[2, 8], &[1f64; 16]);
    assert_rejected(d, &scene, &float64, "expected float32");

    let missing = d.join("missing.npy");
    assert_rejected(d, &scene, &missing, "cannot read");

    let garbage = d.join("garbage.npy");
    std::fs::write(&garbage, b"not an npy file").unwrap();
    assert_rejected(d, &scene, &garbage, "not a valid .npy");

    let nan_dir = d.join("nan_dir.npy");
    write_rays(
        &nan_dir,
        &[
            [0., 0., 5., 0., 0., -1., 0., INF],
            [0., 0., 5., f32::NAN, 0., -1., 0., INF],
        ],
    );
    assert_rejected(
        d,
        &scene,
        &nan_dir,
        "ray 1: direction [NaN, 0e0, -1e0] is NaN; directions must be finite and non-zero",
    );

    let zero_dir = d.join("zero_dir.npy");
    write_rays(&zero_dir, &[[0., 0., 5., 0., 0., 0., 0., INF]]);
    assert_rejected(
        d,
        &scene,
        &zero_dir,
        "ray 0: direction [0e0, 0e0, 0e0] is zero; directions must be finite and non-zero",
    );

    let inf_origin = d.join("inf_origin.npy");
    write_rays(&inf_origin, &[[0., INF, 5., 0., 0., -1., 0., INF]]);
    assert_rejected(
        d,
        &scene,
        &inf_origin,
        "inf_origin.npy: ray 0: origin [0e0, inf, 5e0] is not finite; origins must be finite",
    );

    let nan_t = d.join("nan_t.npy");
    write_rays(&nan_t, &[[0., 0., 5., 0., 0., -1., f32::NAN, INF]]);
    assert_rejected(d, &scene, &nan_t, "ray 0: t_min NaN or t_max inf is NaN");
}

#[test]
fn no_rays_give_an_empty_hits_array() {
    let (dir, scene) = setup();
    let rays_path = dir.path().join("rays.npy");
    write_rays(&rays_path, &[]);
    let out = dir.path().join("hits.npy");
    assert_ok(&run_hits(&scene, &rays_path, &out, &[]));
    let bytes = std::fs::read(&out).unwrap();
    let npy = npyz::NpyFile::new(&bytes[..]).unwrap();
    assert_eq!(npy.shape(), [0, 9]);
}
