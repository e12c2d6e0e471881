//! The accuracy options in every place they can be given — TOML `[render]` keys, `render` and
//! `hits` flags — and what each does: precision changes the primitive tests, offset moves spawn
//! origins, cutoff cuts reflection branches (and 0 changes nothing).

use crate::common;
use crate::npy_rays::write_rays;

use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::geometry::{Offset, Precision};
use lumis_core::render::{RenderOptions, render};
use lumis_core::scene::{Scene, World};
use lumis_io::formats::toml::load_toml_str;
use std::path::Path;
use std::process::Command;

/// A mirror ball over a far ground quad 1e6 from the origin, lit by one point light.
const FAR_SCENE: &str = r#"
[render]
width = 48
height = 32
spp = 1
max_depth = 4
precision = "double"
offset = "epsilon"
epsilon = 0.001
cutoff = 0.2

[camera]
position = [1000000.0, 3.0, 1000010.0]
look_at = [1000000.0, 0.5, 1000000.0]

[materials.mirror]
diffuse = [0.1, 0.1, 0.1]
reflectivity = 0.5

[materials.ground]
diffuse = [0.5, 0.5, 0.5]

[[light]]
type = "point"
position = [1000002.0, 8.0, 1000004.0]
intensity = 300.0

[[sphere]]
center = [1000000.0, 1.0, 1000000.0]
radius = 1.0
material = "mirror"

[[mesh]]
material = "ground"
positions = [[999950.0, 0.0, 999950.0], [1000050.0, 0.0, 999950.0], [1000050.0, 0.0, 1000050.0], [999950.0, 0.0, 1000050.0]]
indices = [[0, 2, 1], [0, 3, 2]]
"#;

fn load(text: &str) -> Scene {
    load_toml_str(text, Path::new("far.toml"), &|p| std::fs::read(p)).expect("valid scene")
}

fn sah(scene: Scene) -> World {
    World::build(scene, AccelKind::Sah, &BuildOptions::default())
}

#[test]
fn toml_render_keys_set_the_accuracy_settings() {
    let st = load(FAR_SCENE).settings().clone();
    assert_eq!(st.precision, Precision::Double);
    assert_eq!(st.offset, Offset::Epsilon(0.001));
    assert_eq!(st.cutoff, 0.2);
    let defaults = load(
        &FAR_SCENE
            .replace("precision = \"double\"\n", "")
            .replace("offset = \"epsilon\"\nepsilon = 0.001\ncutoff = 0.2\n", ""),
    );
    let st = defaults.settings();
    assert_eq!(
        (st.precision, st.offset, st.cutoff),
        (
            Precision::Watertight,
            Offset::ErrorBound,
            lumis_core::scene::DEFAULT_CUTOFF
        )
    );
}

#[test]
fn bad_accuracy_keys_are_errors_naming_the_render_table() {
    for (from, to, what) in [
        (
            "precision = \"double\"",
            "precision = \"quad\"",
            "unknown precision",
        ),
        (
            "offset = \"epsilon\"",
            "offset = \"bump\"",
            "unknown offset",
        ),
        ("epsilon = 0.001", "epsilon = -1.0", "epsilon"),
        ("cutoff = 0.2", "cutoff = 1.5", "cutoff"),
        (
            "offset = \"epsilon\"",
            "offset = \"ulp\"",
            "epsilon is given",
        ),
    ] {
        let err = load_toml_str(&FAR_SCENE.replace(from, to), Path::new("far.toml"), &|p| {
            std::fs::read(p)
        })
        .expect_err(to)
        .to_string();
        assert!(err.contains("far.toml") && err.contains("render"), "{err}");
        assert!(err.contains(what), "{to}: {err}");
    }
}

#[test]
fn cutoff_cuts_weak_branches_and_zero_changes_nothing() {
    let mut world = sah(load(FAR_SCENE));
    let opts = RenderOptions::default();
    let cut = render(&world, &opts).unwrap();
    world.settings_mut().cutoff = 0.0;
    let full = render(&world, &opts).unwrap();
    // The mirror's 0.5 weight passes 0.2 once and 0.25 once more, never 0.125.
    assert!(cut.counts.cut() > 0 && full.counts.cut() == 0);
    assert!(cut.counts.reflection < full.counts.reflection);
    // A zero cutoff is the render without the option at all.
    world.settings_mut().cutoff = 0.0;
    let again = render(&world, &opts).unwrap();
    assert_eq!(again.film.rgba(), full.film.rgba());
}

#[test]
fn precision_and_offset_reach_the_hit_queries() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("far.toml"), FAR_SCENE).unwrap();
    // Rays down onto the ground and the ball.
    let rays: Vec<[f32; 8]> = (0..64)
        .map(|i| {
            let x = 1e6 - 3.0 + 0.1 * i as f32;
            [x, 5.0, 1e6 + 0.3, 0.0, -1.0, 0.01, 0.0, f32::INFINITY]
        })
        .collect();
    write_rays(&dir.path().join("rays.npy"), &rays);
    // The hit records through `lumis hits` (the scene asks for double precision and a 0.001
    // epsilon offset; the flags override them one at a time).
    let hits = |extra: &[&str]| {
        let base = ["hits", "far.toml", "--rays", "rays.npy", "--out", "h.npy"];
        let out = lumis(dir.path(), &[&base[..], extra].concat());
        assert!(
            out.status.success(),
            "{extra:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    hits(&[]);
    let double: Vec<[f32; 9]> = read_rows(&dir.path().join("h.npy"));
    hits(&["--precision", "fast", "--spawn-out", "eps.npy"]);
    let fast: Vec<[f32; 9]> = read_rows(&dir.path().join("h.npy"));
    assert_eq!(double.len(), 64);
    // Both see the same objects; the f32 quadratic loses digits of t on the far ball.
    assert!(double.iter().zip(&fast).all(|(a, b)| a[2] == b[2]));
    assert!(double.iter().zip(&fast).any(|(a, b)| a[0] != b[0]));
    // The epsilon rule puts spawn origins 0.001 off the ground; the error bound an ulp.
    let eps: Vec<[f32; 6]> = read_rows(&dir.path().join("eps.npy"));
    hits(&[
        "--precision",
        "fast",
        "--offset",
        "error-bound",
        "--spawn-out",
        "bound.npy",
    ]);
    let bound: Vec<[f32; 6]> = read_rows(&dir.path().join("bound.npy"));
    assert_eq!((eps.len(), bound.len()), (64, 64));
    let ground = |r: &[f32; 9]| r[2] == 1.0;
    assert!(double.iter().any(ground), "some rays reach the ground");
    for ((row, e), b) in double.iter().zip(&eps).zip(&bound) {
        if ground(row) {
            assert!((e[1] - 0.001).abs() < 1e-6, "epsilon origin {e:?}");
            assert!(b[1] > 0.0 && b[1] < 1e-6, "error-bound origin {b:?}");
            assert!(e[4] < 0.0 && b[4] < 0.0, "far side below the ground");
        }
    }
}

/// Reads an `(N, C)` float32 `.npy` array `lumis hits` wrote, checking its width.
fn read_rows<const C: usize>(path: &Path) -> Vec<[f32; C]> {
    let bytes = std::fs::read(path).unwrap();
    let npy = npyz::NpyFile::new(&bytes[..]).unwrap();
    assert_eq!(npy.shape()[1], C as u64, "{}", path.display());
    let flat: Vec<f32> = npy.into_vec().unwrap();
    flat.chunks_exact(C)
        .map(|c| std::array::from_fn(|i| c[i]))
        .collect()
}

fn lumis(dir: &Path, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_lumis"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn render_and_hits_take_the_flags_and_reject_bad_ones() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("far.toml"), FAR_SCENE).unwrap();
    let base = ["render", "far.toml", "-o", "a.png", "--quiet"];
    let ok = |extra: &[&str]| {
        let out = lumis(dir.path(), &[&base[..], extra].concat());
        assert!(
            out.status.success(),
            "{extra:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    ok(&["--precision", "fast", "--offset", "ulp", "--cutoff", "0"]);
    ok(&[
        "--precision",
        "double",
        "--offset",
        "epsilon",
        "--epsilon",
        "1e-3",
    ]);
    ok(&["--offset", "error-bound", "--cutoff", "0.05"]);
    for (extra, msg) in [
        (
            &["--offset", "ulp", "--epsilon", "1e-3"][..],
            "--epsilon needs --offset epsilon",
        ),
        (&["--offset", "epsilon", "--epsilon", "0"][..], "--epsilon"),
        (&["--cutoff", "2"][..], "--cutoff"),
        (&["--precision", "quad"][..], "quad"),
    ] {
        let out = lumis(dir.path(), &[&base[..], extra].concat());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(msg),
            "{extra:?}: {err}"
        );
    }
    // hits: the same flags, and the spawn origins file.
    write_rays(
        &dir.path().join("rays.npy"),
        &[[1e6f32, 5.0, 1e6 + 3.0, 0.0, -1.0, 0.0, 0.0, f32::INFINITY]],
    );
    let out = lumis(
        dir.path(),
        &[
            "hits",
            "far.toml",
            "--rays",
            "rays.npy",
            "--out",
            "h.npy",
            "--precision",
            "fast",
            "--offset",
            "epsilon",
            "--epsilon",
            "0.01",
            "--spawn-out",
            "s.npy",
        ],
    );
    common::cli::assert_ok(&out);
    let s = std::fs::read(dir.path().join("s.npy")).unwrap();
    let npy = npyz::NpyFile::new(&s[..]).unwrap();
    assert_eq!(npy.shape(), &[1, 6]);
    let v: Vec<f32> = npy.into_vec().unwrap();
    assert!(
        (v[1] - 0.01).abs() < 1e-6 && (v[4] + 0.01).abs() < 1e-6,
        "{v:?}"
    );
}
