//! §2 and §3 through the command line: `--stats-json` reports rays by kind and by reason, and a
//! scene without an effect traces zero rays of its kind.

use serde_json::Value;
use std::path::Path;
use std::process::Command;

const MATTE: &str = r#"
[render]
width = 20
height = 12
spp = 1
[camera]
position = [0.0, 2.0, 5.0]
look_at = [0.0, 0.5, 0.0]
fov = 50.0
[materials.clay]
diffuse = [0.6, 0.4, 0.3]
[[sphere]]
center = [0.0, 0.5, 0.0]
radius = 0.5
material = "clay"
[[sphere]]
center = [0.0, -1000.0, 0.0]
radius = 1000.0
material = "clay"
"#;

const LIGHT: &str = r#"
[[light]]
type = "point"
position = [2.0, 4.0, 3.0]
intensity = 40.0
"#;

const MIRROR: &str = r#"
[materials.mirror]
reflectivity = 0.8
[[sphere]]
center = [1.2, 0.5, 0.0]
radius = 0.5
material = "mirror"
"#;

/// Renders `toml` with `args` and returns the `--stats-json` report.
fn stats(dir: &Path, name: &str, toml: &str, args: &[&str]) -> Value {
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, toml).expect("write scene");
    let json = dir.join(format!("{name}.json"));
    let out = Command::new(env!("CARGO_BIN_EXE_lumis"))
        .arg(&scene)
        .args(args)
        .arg("--stats-json")
        .arg(&json)
        .arg("-q")
        .current_dir(dir)
        .output()
        .expect("run lumis");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_str(&std::fs::read_to_string(&json).expect("report")).expect("json")
}

fn rays(v: &Value, kind: &str) -> u64 {
    v["rays"][kind]
        .as_u64()
        .unwrap_or_else(|| panic!("rays.{kind} in {v}"))
}

#[test]
fn a_scene_without_an_effect_traces_no_rays_of_its_kind() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let pixels = 20 * 12;

    let no_lights = stats(d, "dark", MATTE, &["-o", "dark.png"]);
    assert_eq!(rays(&no_lights, "shadow"), 0);
    assert_eq!(no_lights["effects"]["shadows"]["on"], false);
    assert_eq!(
        no_lights["effects"]["shadows"]["reason"],
        "the scene has no lights"
    );

    let lit = format!("{MATTE}{LIGHT}");
    let matte = stats(d, "matte", &lit, &["-o", "matte.png"]);
    assert!(rays(&matte, "shadow") > 0);
    assert_eq!(rays(&matte, "reflection"), 0);
    assert_eq!(rays(&matte, "refraction"), 0);
    // PNG only: no AOV rays, one skipped per pixel.
    assert_eq!(rays(&matte, "aov"), 0);
    assert_eq!(matte["rays"]["not_traced"]["aov"], pixels);
    assert_eq!(rays(&matte, "camera"), pixels);

    let exr = stats(d, "matte_exr", &lit, &["-o", "matte.exr"]);
    assert_eq!(rays(&exr, "aov"), pixels);

    let mirror = stats(d, "mirror", &format!("{lit}{MIRROR}"), &["-o", "m.png"]);
    assert!(rays(&mirror, "reflection") > 0);
    assert_eq!(rays(&mirror, "refraction"), 0);
    assert_eq!(
        mirror["effects"]["refraction"]["reason"],
        "no material transmits"
    );
}

#[test]
fn effects_all_traces_more_and_writes_the_same_png() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let scene = format!("{MATTE}{LIGHT}{MIRROR}");
    let auto = stats(d, "a", &scene, &["-o", "auto.png", "--cutoff", "0"]);
    let all = stats(d, "b", &scene, &["-o", "all.png", "--effects", "all"]);
    assert_eq!(all["effects"]["mode"], "all");
    assert!(rays(&all, "total") > rays(&auto, "total"));
    assert!(rays(&all, "refraction") > 0);
    let png = |n: &str| std::fs::read(d.join(n)).expect("png");
    assert!(png("auto.png") == png("all.png"), "PNG bytes differ");
}

#[test]
fn stats_json_may_not_overwrite_an_image() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = Command::new(env!("CARGO_BIN_EXE_lumis"))
        .args(["-o", "x.png", "--stats-json", "x.png", "-q"])
        .current_dir(dir.path())
        .output()
        .expect("run lumis");
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--stats-json"));
    assert!(!dir.path().join("x.png").exists());
}
