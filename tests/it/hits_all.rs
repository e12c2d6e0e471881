//! `lumis hits --all`: every crossing and graze per ray as float32 `.npy` (M, 11) — ray index,
//! the nine nearest-hit columns, graze flag — on a sphere and a closed octahedron: known
//! answers, the first hit of each ray equal to the nearest-hit row, thread-count
//! independence, and `--all --any-hit` refused.

use crate::npy_rays::write_rays;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A unit sphere at the origin (primitive 0, object 0) and the octahedron
/// |x - 10| + |y| + |z| <= 3 (primitives 1..=8, object 1).
const SCENE: &str = "[camera]
position = [0.0, 0.0, 20.0]
look_at = [0.0, 0.0, 0.0]

[materials.m]
diffuse = [0.5, 0.5, 0.5]

[[sphere]]
name = \"ball\"
center = [0.0, 0.0, 0.0]
radius = 1.0
material = \"m\"

[[mesh]]
name = \"octahedron\"
material = \"m\"
positions = [[13.0, 0.0, 0.0], [7.0, 0.0, 0.0], [10.0, 3.0, 0.0], [10.0, -3.0, 0.0], [10.0, 0.0, 3.0], [10.0, 0.0, -3.0]]
indices = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]
";

const INF: f32 = f32::INFINITY;

fn setup() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, SCENE).unwrap();
    (dir, scene)
}

/// Reads a float32 2-D array: (shape, rows).
fn read_f32(path: &Path) -> (Vec<u64>, Vec<Vec<f32>>) {
    let bytes = std::fs::read(path).unwrap();
    let npy = npyz::NpyFile::new(&bytes[..]).unwrap();
    let shape = npy.shape().to_vec();
    let flat: Vec<f32> = npy.into_vec().unwrap();
    let rows = flat
        .chunks(shape[1].max(1) as usize)
        .map(<[f32]>::to_vec)
        .collect();
    (shape, rows)
}

fn run_hits(scene: &Path, rays: &Path, out: &Path, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lumis"))
        .arg("hits")
        .arg(scene)
        .arg("--rays")
        .arg(rays)
        .arg("--out")
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

fn assert_ok(o: &Output) {
    assert!(
        o.status.success(),
        "lumis hits failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The rays and their `(ray index, t, primitive, graze)` rows.
fn rays() -> Vec<[f32; 8]> {
    vec![
        // 0: through the sphere: in at 4, out at 6.
        [0., 0., 5., 0., 0., -1., 0., INF],
        // 1: tangent to the sphere at (1, 0, 0): one graze.
        [1., 0., 5., 0., 0., -1., 0., INF],
        // 2: misses everything: no row.
        [0., 50., 5., 0., 0., -1., 0., INF],
        // 3: down through the octahedron's top and bottom vertices: two crossings.
        [10., 0., 5., 0., 0., -1., 0., INF],
        // 4: across its vertex (13, 0, 0) only: a graze.
        [13., -2., 0., 0., 1., 0., 0., INF],
        // 5: in and out through its edges at (11.5, 1.5, 0) and (8.5, -1.5, 0).
        [13.5, 3.5, 0., -1., -1., 0., 0., INF],
    ]
}

#[test]
fn all_hits_rows_give_each_crossing_once_and_flag_grazes() {
    let (dir, scene) = setup();
    let (rays_path, out) = (dir.path().join("rays.npy"), dir.path().join("all.npy"));
    write_rays(&rays_path, &rays());
    assert_ok(&run_hits(&scene, &rays_path, &out, &["--all"]));
    let (shape, rows) = read_f32(&out);
    assert_eq!(shape, [8, 11]);
    let got: Vec<(f32, f32, f32, f32)> = rows.iter().map(|r| (r[0], r[1], r[10], r[9])).collect();
    // (ray, t, graze, kind)
    assert_eq!(
        got,
        [
            (0., 4., 0., 0.),
            (0., 6., 0., 0.),
            (1., 5., 1., 0.),
            (3., 2., 0., 1.),
            (3., 8., 0., 1.),
            (4., 2., 1., 1.),
            (5., 2., 0., 1.),
            (5., 5., 0., 1.),
        ]
    );
    // Sphere rows: primitive 0, object 0, outward normals; octahedron rows: object 1.
    assert_eq!(&rows[0][1..9], &[4., 0., 0., 0., 0., 0., 0., 1.]);
    assert_eq!(&rows[1][1..9], &[6., 0., 0., 0., 0., 0., 0., -1.]);
    assert!(
        rows[3..]
            .iter()
            .all(|r| (1.0..=8.0).contains(&r[2]) && r[3] == 1.0)
    );

    // Each ray's first row is its nearest-hit row, column for column.
    let nearest = dir.path().join("nearest.npy");
    assert_ok(&run_hits(&scene, &rays_path, &nearest, &[]));
    let (nshape, nrows) = read_f32(&nearest);
    assert_eq!(nshape, [6, 9], "the nearest-hit output is unchanged");
    for (i, n) in nrows.iter().enumerate() {
        let first = rows.iter().find(|r| r[0] == i as f32);
        match first {
            Some(r) => assert_eq!(&r[1..10], &n[..], "ray {i}"),
            None => assert_eq!(n[0], INF, "ray {i}"),
        }
    }
}

#[test]
fn all_hits_do_not_depend_on_the_thread_count_or_the_accelerator() {
    let (dir, scene) = setup();
    let rays_path = dir.path().join("rays.npy");
    // Many rays (several parallel chunks), many through the octahedron's vertices and edges.
    let mut rays = Vec::new();
    for i in 0..3000 {
        let (a, b) = ((i % 61) as f32 - 30.0, (i / 61) as f32 - 25.0);
        rays.push([10. + a * 0.125, b * 0.125, 6., 0., 0., -1., 0., INF]);
        rays.push([a * 0.05, b * 0.05, 6., 0.25, 0.5, -1., 0., INF]);
    }
    write_rays(&rays_path, &rays);
    let mut outputs = Vec::new();
    for extra in [
        &["--threads", "1"][..],
        &["--threads", "3"],
        &["--accel", "brute"],
        &["--accel", "bsp"],
    ] {
        let out = dir.path().join(format!("all{}.npy", outputs.len()));
        let mut args = vec!["--all"];
        args.extend(extra);
        assert_ok(&run_hits(&scene, &rays_path, &out, &args));
        outputs.push(std::fs::read(&out).unwrap());
    }
    assert!(outputs.windows(2).all(|w| w[0] == w[1]));
    let (shape, rows) = read_f32(&dir.path().join("all0.npy"));
    assert!(shape[0] > 2000, "{shape:?}");
    assert!(rows.iter().any(|r| r[10] == 1.0), "some graze");
}

#[test]
fn all_and_any_hit_together_are_refused() {
    let (dir, scene) = setup();
    let (rays_path, out) = (dir.path().join("rays.npy"), dir.path().join("all.npy"));
    write_rays(&rays_path, &rays());
    let o = run_hits(&scene, &rays_path, &out, &["--all", "--any-hit"]);
    assert!(!o.status.success());
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("--any-hit"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(!out.exists());
}
