//! `--env-sun`: the map's sun becomes a directional light named `sun` that casts a hard
//! shadow where the sun's direction says, with its own per-light pass; a map without a sun is
//! refused with the reason.

use super::write_hdr;
use crate::common::exr::channel;
use crate::exr_passes::{at, lumis, render};

/// Seen from straight above (orthographic, image up = -Z, 4 pixels per unit): a ball of
/// radius 0.5 at height 1 over a matte ground.
const SCENE: &str = r#"
[render]
spp = 2
[camera]
type = "orthographic"
height = 6.0
position = [0.0, 10.0, 0.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 0.0, -1.0]
[materials.matte]
diffuse = [0.5, 0.5, 0.5]
[[sphere]]
center = [0.0, 1.0, 0.0]
radius = 0.5
material = "matte"
[[mesh]]
name = "ground"
positions = [[-8.0, 0.0, -8.0], [8.0, 0.0, -8.0], [8.0, 0.0, 8.0], [-8.0, 0.0, 8.0]]
indices = [[0, 2, 1], [0, 3, 2]]
material = "matte"
"#;

/// A dim uniform sky with a sun disk of radius 0.05 rad 60 degrees up towards -Z.
fn sky(u: f32, v: f32) -> [f32; 3] {
    let (t, p) = (v * std::f32::consts::PI, u * std::f32::consts::TAU);
    let d = [p.sin() * t.sin(), t.cos(), -p.cos() * t.sin()];
    let sun = [0.0, 0.866_025_4, -0.5];
    let cos = d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2];
    if cos > 0.05f32.cos() {
        [2000.0; 3]
    } else {
        [0.2; 3]
    }
}

#[test]
fn the_sun_casts_its_shadow_away_from_itself() {
    let dir = tempfile::tempdir().unwrap();
    write_hdr(&dir.path().join("sky.hdr"), 256, 128, sky);
    let args = ["--env", "sky.hdr", "--env-sun", "--aov", "lights"];
    let image = render(dir.path(), "s.toml", SCENE, "o.exr", &args);
    let sun = channel(&image, "light.sun.R");
    let ids = channel(&image, "id.object");
    // The sun is towards -Z, 60 degrees up: the ball's shadow falls towards +Z (down the
    // image), on the ground from z = 0 to z = 0.5 / sin 60 = 0.58, beyond the ball's disk.
    let (shadowed, lit, beside) = (at(16, 15), at(16, 20), at(16, 8));
    assert_eq!(ids[shadowed], 1.0, "the ground at (16, 15)");
    assert_eq!(sun[shadowed], 0.0, "the ball shadows the ground towards +Z");
    assert!(
        sun[lit] > 0.1 && sun[beside] > 0.1,
        "{} {}",
        sun[lit],
        sun[beside]
    );
    let r = channel(&image, "R");
    assert!(r[shadowed] < 0.5 * r[lit], "{} vs {}", r[shadowed], r[lit]);
}

#[test]
fn a_map_without_a_sun_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    write_hdr(&dir.path().join("flat.hdr"), 64, 32, |_, _| [0.5; 3]);
    let out = lumis(dir.path())
        .args(["-o", "o.png", "--width", "8", "--height", "6", "--quiet"])
        .args(["--env", "flat.hdr", "--env-sun"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("--env-sun") && err.contains("stands out"),
        "{err}"
    );
}
