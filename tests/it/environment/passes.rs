//! The light-path passes add up to the beauty on every pixel, and the per-light passes to the
//! direct light, on scenes with every kind of path: glass in front of a mirror, an emitter,
//! two named lights, an environment seen directly and through reflection and refraction.
//!
//! Tolerance: per channel `|sum - beauty| <= 1e-5 * (|beauty| + sum of |terms|) + 1e-7`. The
//! sums differ from the beauty only by float rounding: the beauty adds each sample's terms in
//! shading order and multiplies each light by (diffuse + Phong) before the cosine, the passes
//! add per term and split that product, so each of the ~10 additions and products per sample
//! contributes at most an ulp (6e-8 relative) of the largest term. 1e-5 is ~20x that bound,
//! and a missing or double-counted term (the bugs this looks for) is orders of magnitude
//! larger on the pixels where it matters.

use super::{quarters, write_hdr};
use crate::common::exr::{FlatImage, channel};
use crate::exr_passes::{lumis, names, ok, render};

const PATHS: [&str; 7] = [
    "diffuse",
    "specular",
    "reflection",
    "refraction",
    "emission",
    "ambient",
    "background",
];

/// Glass sphere in front of a mirror wall, an emissive ball, a shiny red ball, a floor, two
/// named lights, and the `sky.hdr` environment around it all.
const SCENE: &str = r#"
[render]
spp = 2
max_depth = 6
[camera]
position = [0.0, 1.0, 6.0]
look_at = [0.0, 0.5, 0.0]
fov = 50.0
[materials.glass]
diffuse = [0.0, 0.0, 0.0]
transmission = 1.0
ior = 1.5
[materials.mirror]
diffuse = [0.05, 0.05, 0.05]
reflectivity = 0.9
[materials.glow]
diffuse = [0.1, 0.1, 0.1]
emission = [2.0, 1.5, 0.5]
[materials.red]
diffuse = [0.7, 0.1, 0.1]
specular = [0.5, 0.5, 0.5]
shininess = 40.0
reflectivity = 0.2
[materials.floor]
diffuse = [0.6, 0.6, 0.6]
[[light]]
name = "key"
type = "point"
position = [3.0, 5.0, 4.0]
intensity = 40.0
[[light]]
name = "rim light"
type = "directional"
direction = [-1.0, -1.0, -0.5]
color = [0.6, 0.7, 1.0]
intensity = 1.5
[[sphere]]
center = [0.0, 0.8, 1.5]
radius = 0.8
material = "glass"
[[sphere]]
center = [0.0, 1.0, -3.0]
radius = 2.5
material = "mirror"
[[sphere]]
center = [-1.8, 0.4, 0.5]
radius = 0.4
material = "glow"
[[sphere]]
center = [1.7, 0.5, 0.0]
radius = 0.5
material = "red"
[[mesh]]
positions = [[-8.0, 0.0, -8.0], [8.0, 0.0, -8.0], [8.0, 0.0, 8.0], [-8.0, 0.0, 8.0]]
indices = [[0, 2, 1], [0, 3, 2]]
material = "floor"
[environment]
file = "sky.hdr"
rotation = 30.0
"#;

/// Checks both sums on every pixel of `image` (lumis layout), with `lights` the per-light
/// layer names.
fn assert_sums(image: &FlatImage, lights: &[&str], what: &str) {
    for c in ["R", "G", "B"] {
        let beauty = channel(image, c);
        let terms: Vec<Vec<f32>> = PATHS
            .iter()
            .map(|p| channel(image, &format!("{p}.{c}")))
            .collect();
        let per_light: Vec<Vec<f32>> = lights
            .iter()
            .map(|l| channel(image, &format!("light.{l}.{c}")))
            .collect();
        for i in 0..beauty.len() {
            let sum: f32 = terms.iter().map(|t| t[i]).sum();
            let scale: f32 = beauty[i].abs() + terms.iter().map(|t| t[i].abs()).sum::<f32>();
            assert!(
                (sum - beauty[i]).abs() <= 1e-5 * scale + 1e-7,
                "{what}: pixel {i} {c}: passes add up to {sum}, beauty {}",
                beauty[i]
            );
            let direct = terms[0][i] + terms[1][i];
            let lights: f32 = per_light.iter().map(|t| t[i]).sum();
            let scale = direct.abs() + per_light.iter().map(|t| t[i].abs()).sum::<f32>();
            assert!(
                (lights - direct).abs() <= 1e-5 * scale + 1e-7,
                "{what}: pixel {i} {c}: lights add up to {lights}, diffuse + specular {direct}"
            );
        }
    }
}

fn sky(dir: &std::path::Path) {
    write_hdr(&dir.join("sky.hdr"), 64, 32, |u, v| {
        let q = quarters(u, v);
        [
            q[0] * 0.5 + 0.1,
            q[1] * 0.5 + 0.1,
            q[2] * 0.5 + (1.0 - v) * 0.3,
        ]
    });
}

#[test]
fn passes_add_up_to_the_beauty_and_lights_to_the_direct_light() {
    let dir = tempfile::tempdir().unwrap();
    sky(dir.path());
    let aov = ["--aov", "lightpaths,lights"];
    let image = render(dir.path(), "s.toml", SCENE, "o.exr", &aov);
    assert_sums(&image, &["key", "rim_light"], "glass before a mirror");
    // Every path is exercised somewhere (else the check above proves little).
    for p in PATHS {
        let any = ["R", "G", "B"].iter().any(|c| {
            channel(&image, &format!("{p}.{c}"))
                .iter()
                .any(|v| *v > 1e-4)
        });
        assert!(any, "pass {p} is black everywhere");
    }
    // The passes do not change the beauty: the same bits as a render without them.
    let plain = render(dir.path(), "s.toml", SCENE, "p.exr", &[]);
    for c in ["R", "G", "B", "A"] {
        assert_eq!(channel(&image, c), channel(&plain, c), "beauty {c}");
    }
    // Transparent misses: the background pass is then black too, and the sum still holds.
    let args = ["--aov", "lightpaths,lights", "--transparent"];
    let clear = render(dir.path(), "s.toml", SCENE, "t.exr", &args);
    assert_sums(&clear, &["key", "rim_light"], "transparent");
}

#[test]
fn the_default_scene_splits_too_and_blender_names_hold_the_same_values() {
    let dir = tempfile::tempdir().unwrap();
    let run = |layout: &str, out: &str| {
        ok(lumis(dir.path())
            .args([
                "-o", out, "--float", "--quiet", "--width", "48", "--height", "27",
            ])
            .args(["--aov", "lightpaths,lights", "--layout", layout])
            .output()
            .unwrap());
        crate::common::exr::read_exr(&dir.path().join(out))
    };
    let own = run("lumis", "l.exr");
    assert_sums(&own, &["light0", "light1"], "default scene");
    let blender = run("blender", "b.exr");
    let have = names(&blender);
    for (lumis_name, blender_name) in [
        ("diffuse", "DiffDir"),
        ("specular", "GlossDir"),
        ("reflection", "GlossInd"),
        ("refraction", "TransInd"),
        ("emission", "Emit"),
        ("background", "Env"),
        ("ambient", "Ambient"),
        ("light.light0", "Combined_light0"),
    ] {
        for c in ["R", "G", "B"] {
            let name = format!("ViewLayer.{blender_name}.{c}");
            assert!(have.contains(&name), "no {name} in {have:?}");
            assert_eq!(
                channel(&blender, &name),
                channel(&own, &format!("{lumis_name}.{c}")),
                "{name}"
            );
        }
    }
}
