//! What is written only on request: no optional layer unless asked for, exactly the layers
//! asked for, nothing extra (and no failure) for a PNG-only render, a clear error for an
//! unknown pass.

use crate::exr_passes::{CAMERA, lumis, names, ok, render};

const SCENE: &str = "
[[sphere]]
center = [0.0, 0.0, 0.0]
radius = 1.0

[[light]]
type = \"directional\"
direction = [0.0, 0.0, -1.0]
intensity = 1.0
";

const DEFAULT_CHANNELS: [&str; 10] = [
    "A",
    "B",
    "G",
    "N.X",
    "N.Y",
    "N.Z",
    "R",
    "Z",
    "id.object",
    "id.prim",
];

#[test]
fn optional_layers_only_on_request() {
    let dir = tempfile::tempdir().unwrap();
    let scene = format!("{CAMERA}{SCENE}");
    let with = |extra: &[&str], out: &str| -> Vec<String> {
        let mut v = names(&render(dir.path(), "s.toml", &scene, out, extra));
        v.sort();
        v
    };
    let sorted = |extra: &[&str]| {
        let mut v: Vec<String> = DEFAULT_CHANNELS
            .iter()
            .chain(extra)
            .map(|s| s.to_string())
            .collect();
        v.sort();
        v
    };
    assert_eq!(with(&[], "d.exr"), sorted(&[]));
    // --transparent and --layout lumis add no channel either.
    assert_eq!(
        with(&["--transparent", "--layout", "lumis"], "t.exr"),
        sorted(&[])
    );
    assert_eq!(with(&["--aov", "uv"], "u.exr"), sorted(&["uv.U", "uv.V"]));
    assert_eq!(
        with(&["--aov", "position", "--aov", "albedo"], "pa.exr"),
        sorted(&["P.X", "P.Y", "P.Z", "albedo.B", "albedo.G", "albedo.R"])
    );
}

#[test]
fn aov_with_a_png_only_output_writes_just_the_png() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), format!("{CAMERA}{SCENE}")).unwrap();
    let png = |name: &str, extra: &[&str]| {
        ok(lumis(dir.path())
            .args([
                "s.toml", "-o", name, "--quiet", "--width", "32", "--height", "24",
            ])
            .args(extra)
            .output()
            .unwrap());
        std::fs::read(dir.path().join(name)).unwrap()
    };
    let plain = png("plain.png", &[]);
    let passes = png(
        "aov.png",
        &["--aov", "albedo,position,uv", "--layout", "blender"],
    );
    assert!(plain == passes, "the PNG does not depend on EXR-only flags");
    let mut files: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert_eq!(files, ["aov.png", "plain.png", "s.toml"]);
}

#[test]
fn an_unknown_aov_is_a_clap_error_naming_the_choices() {
    let dir = tempfile::tempdir().unwrap();
    let out = lumis(dir.path())
        .args(["--aov", "albedo,foo", "-o", "x.exr", "--quiet"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "clap's usage error: {err}");
    assert!(
        err.contains("invalid value 'foo' for '--aov <LIST>'"),
        "{err}"
    );
    assert!(err.contains("albedo") && err.contains("position") && err.contains("uv"));
    assert!(
        std::fs::read_dir(dir.path()).unwrap().next().is_none(),
        "nothing written"
    );
}
