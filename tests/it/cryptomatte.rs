//! Cryptomatte pixels, read back from the EXR with the exr crate: coverage against alpha,
//! interior and edge pixels, ids against hashes computed outside lumis (by
//! tools/lumis_tools/cryptomatte.py, written from the specification), the manifest, the number
//! of layers per level count, and that threads, crops and PNG-only renders change nothing.

use crate::common;

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

use common::exr::{FlatImage, channel, read_exr};
use exr::prelude::AttributeValue;

/// Two quads touching along a vertical edge (`left` red, `right` blue) with background around
/// them, and a small third quad also called `left` but blue, top left: its object matte merges
/// with the big left quad's, its material matte with the right quad's.
const SCENE: &str = r#"
[render]
width = 48
height = 24
spp = 4
background = [0.2, 0.3, 0.4]

[camera]
position = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
fov = 40.0

[materials.red]
diffuse = [0.8, 0.1, 0.1]

[materials.blue]
diffuse = [0.1, 0.1, 0.8]

[materials.unused]

[[light]]
type = "point"
position = [0.0, 0.0, 6.0]
intensity = 80.0

[[mesh]]
name = "left"
material = "red"
positions = [[-2.5, -1.0, 0.0], [0.37, -1.0, 0.0], [0.37, 1.0, 0.0], [-2.5, 1.0, 0.0]]
indices = [[0, 1, 2], [0, 2, 3]]

[[mesh]]
name = "right"
material = "blue"
positions = [[0.37, -1.0, 0.0], [2.0, -1.0, 0.0], [2.0, 1.0, 0.0], [0.37, 1.0, 0.0]]
indices = [[0, 1, 2], [0, 2, 3]]

[[mesh]]
name = "left"
material = "blue"
positions = [[-3.4, 1.2, 0.0], [-2.8, 1.2, 0.0], [-2.8, 1.7, 0.0], [-3.4, 1.7, 0.0]]
indices = [[0, 1, 2], [0, 2, 3]]
"#;

const W: usize = 48;
const H: usize = 24;

/// Float bits of the ids, from the Python implementation (`name_id_bits`), not from lumis.
const LEFT: u32 = 0xa94a_3318;
const RIGHT: u32 = 0x6a7c_91ff;
const RED: u32 = 0xeb50_26fd;
const BLUE: u32 = 0xe8c3_f103;
/// Metadata keys of the two types (first 7 hex digits of the type name's MurmurHash3).
const OBJECT_KEY: &str = "3ae39a5";
const MATERIAL_KEY: &str = "be359d6";
/// The key of `ViewLayer.CryptoObject` (`--layout blender`).
const BLENDER_OBJECT_KEY: &str = "542cafa";

fn lumis(dir: &Path, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_lumis"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

/// Renders the scene in `dir` to `out` with `--cryptomatte --transparent --float` and `extra`.
fn render(dir: &Path, out: &str, extra: &[&str]) -> FlatImage {
    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    let mut args = vec!["render", "scene.toml", "-o", out, "--quiet", "--float"];
    args.extend(["--cryptomatte", "--transparent"]);
    args.extend(extra);
    let o = lumis(dir, &args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    read_exr(&dir.join(out))
}

/// The (id bits, coverage) ranks of every pixel of type `name` (`levels` from the channels).
fn ranks(image: &FlatImage, name: &str) -> Vec<Vec<(u32, f32)>> {
    let mut layers = Vec::new();
    while has(image, &format!("{name}{:02}.R", layers.len())) {
        let c = |ch: &str| channel(image, &format!("{name}{:02}.{ch}", layers.len()));
        layers.push([c("R"), c("G"), c("B"), c("A")]);
    }
    assert!(!layers.is_empty(), "no {name}00 layer");
    let pixels = layers[0][0].len();
    (0..pixels)
        .map(|p| {
            (layers.iter())
                .flat_map(|l| [(l[0][p].to_bits(), l[1][p]), (l[2][p].to_bits(), l[3][p])])
                .collect()
        })
        .collect()
}

fn has(image: &FlatImage, name: &str) -> bool {
    let list = &image.layer_data[0].channel_data.list;
    list.iter().any(|c| c.name == *name)
}

/// The matte of id `bits`: its coverage summed over ranks.
fn matte(pixel: &[(u32, f32)], bits: u32) -> f32 {
    pixel.iter().filter(|r| r.0 == bits).map(|r| r.1).sum()
}

fn text_attribute(image: &FlatImage, name: &str) -> Option<String> {
    let attrs = &image.layer_data[0].attributes.other;
    attrs.iter().find_map(|(k, v)| match v {
        AttributeValue::Text(t) if *k == *name => Some(t.to_string()),
        _ => None,
    })
}

/// The manifest of the type with metadata key `key`, parsed.
fn manifest(image: &FlatImage, key: &str) -> BTreeMap<String, String> {
    let json = text_attribute(image, &format!("cryptomatte/{key}/manifest")).expect("manifest");
    serde_json::from_str(&json).unwrap()
}

#[test]
fn coverage_sums_to_alpha_with_interiors_and_shared_edges() {
    let dir = tempfile::tempdir().unwrap();
    let image = render(dir.path(), "a.exr", &[]);
    let alpha = channel(&image, "A");
    let (mut shared, mut background_edge, mut interior) = (0, 0, 0);
    for (kind, ids) in [
        ("CryptoObject", [LEFT, RIGHT]),
        ("CryptoMaterial", [RED, BLUE]),
    ] {
        let ranks = ranks(&image, kind);
        assert_eq!(ranks.len(), W * H);
        for (p, px) in ranks.iter().enumerate() {
            // Every id a pixel holds is one of the two names; empty ranks are (0, 0).
            for &(id, c) in px {
                assert!(
                    ids.contains(&id) || (id, c) == (0, 0.0),
                    "{kind} pixel {p}: {id:#x}"
                );
            }
            let sum: f32 = ids.iter().map(|&id| matte(px, id)).sum();
            assert!(
                (sum - alpha[p]).abs() < 1e-6,
                "{kind} pixel {p}: {sum} vs A {}",
                alpha[p]
            );
            let (a, b) = (matte(px, ids[0]), matte(px, ids[1]));
            if kind == "CryptoObject" {
                shared += usize::from(a > 0.0 && a < 1.0 && b > 0.0 && b < 1.0);
                background_edge += usize::from((a + b) > 0.0 && (a + b) < 1.0);
                interior += usize::from(px[0].1 == 1.0 && px[1] == (0, 0.0));
            }
        }
    }
    assert!(shared >= 8, "{shared} pixels shared by left and right");
    assert!(
        background_edge >= 20,
        "{background_edge} edge pixels over the background"
    );
    assert!(interior >= 100, "{interior} interior pixels");
}

#[test]
fn pixels_name_the_objects_and_materials_by_their_hashes() {
    let dir = tempfile::tempdir().unwrap();
    let image = render(dir.path(), "a.exr", &[]);
    let (objects, materials) = (
        ranks(&image, "CryptoObject"),
        ranks(&image, "CryptoMaterial"),
    );
    let at = |x: usize, y: usize| y * W + x;
    // Inside the big left quad, the right quad, the small "left" quad; the background.
    for (x, y, object, material) in [
        (10, 12, LEFT, RED),
        (35, 12, RIGHT, BLUE),
        (2, 2, LEFT, BLUE),
    ] {
        assert_eq!(objects[at(x, y)][0], (object, 1.0), "object at ({x}, {y})");
        assert_eq!(
            materials[at(x, y)][0],
            (material, 1.0),
            "material at ({x}, {y})"
        );
        assert_eq!(objects[at(x, y)][1], (0, 0.0));
    }
    assert!(objects[at(46, 1)].iter().all(|&r| r == (0, 0.0)));
    assert_eq!(channel(&image, "A")[at(46, 1)], 0.0);
    // The two objects called "left" are one name: one manifest entry, one id.
    let object_manifest = manifest(&image, OBJECT_KEY);
    let want = |pairs: &[(&str, u32)]| -> BTreeMap<String, String> {
        (pairs
            .iter()
            .map(|(n, id)| (n.to_string(), format!("{id:08x}"))))
        .collect()
    };
    assert_eq!(object_manifest, want(&[("left", LEFT), ("right", RIGHT)]));
    // Only the materials objects use ("unused" is left out).
    assert_eq!(
        manifest(&image, MATERIAL_KEY),
        want(&[("blue", BLUE), ("red", RED)])
    );
    for (key, name) in [
        (OBJECT_KEY, "CryptoObject"),
        (MATERIAL_KEY, "CryptoMaterial"),
    ] {
        let attr = |f: &str| text_attribute(&image, &format!("cryptomatte/{key}/{f}"));
        assert_eq!(attr("name").as_deref(), Some(name));
        assert_eq!(attr("hash").as_deref(), Some("MurmurHash3_32"));
        assert_eq!(attr("conversion").as_deref(), Some("uint32_to_float32"));
    }
}

#[test]
fn levels_set_the_number_of_rgba_layers() {
    let dir = tempfile::tempdir().unwrap();
    let two = render(dir.path(), "two.exr", &["--cryptomatte-levels", "2"]);
    assert!(has(&two, "CryptoObject00.A") && !has(&two, "CryptoObject01.R"));
    let three = render(dir.path(), "three.exr", &["--cryptomatte-levels", "3"]);
    assert!(has(&three, "CryptoObject01.A") && !has(&three, "CryptoObject02.R"));
    for ch in ["B", "A"] {
        for kind in ["CryptoObject", "CryptoMaterial"] {
            let v = channel(&three, &format!("{kind}01.{ch}"));
            assert!(
                v.iter().all(|&x| x.to_bits() == 0),
                "{kind}01.{ch} not zero"
            );
        }
    }
    let o = lumis(
        dir.path(),
        &[
            "render",
            "scene.toml",
            "-o",
            "z.exr",
            "--cryptomatte",
            "--cryptomatte-levels",
            "0",
        ],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("--cryptomatte-levels 0"),
        "{err}"
    );
    assert!(!dir.path().join("z.exr").exists());
}

/// Every Cryptomatte channel's samples, by name.
fn crypto_channels(image: &FlatImage) -> BTreeMap<String, Vec<u32>> {
    let list = &image.layer_data[0].channel_data.list;
    (list.iter())
        .map(|c| c.name.to_string())
        .filter(|n| n.starts_with("Crypto"))
        .map(|n| {
            let bits = channel(image, &n).iter().map(|v| v.to_bits()).collect();
            (n, bits)
        })
        .collect()
}

#[test]
fn threads_and_crops_change_no_cryptomatte_pixel() {
    let dir = tempfile::tempdir().unwrap();
    let one = crypto_channels(&render(dir.path(), "t1.exr", &["--threads", "1"]));
    let three = crypto_channels(&render(dir.path(), "t3.exr", &["--threads", "3"]));
    assert_eq!(one.len(), 24, "3 RGBA layers of 2 types");
    assert_eq!(one, three);
    // Pixels 12..36 x 6..18 (the shared edge at column 26 runs through them).
    let crop = render(dir.path(), "crop.exr", &["--pixel-bounds", "12,36,6,18"]);
    let crop = crypto_channels(&crop);
    for (name, full) in &one {
        let part = &crop[name];
        assert_eq!(part.len(), 24 * 12, "{name}");
        for (i, &v) in part.iter().enumerate() {
            let (x, y) = (12 + i % 24, 6 + i / 24);
            assert_eq!(v, full[y * W + x], "{name} at ({x}, {y})");
        }
    }
}

#[test]
fn a_png_only_render_writes_no_exr() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.toml"), SCENE).unwrap();
    let o = lumis(
        dir.path(),
        &[
            "render",
            "scene.toml",
            "-o",
            "only.png",
            "--cryptomatte",
            "--quiet",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let files: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(dir.path().join("only.png").exists());
    assert!(!files.iter().any(|f| f.ends_with(".exr")), "{files:?}");
}

#[test]
fn blender_layout_has_the_same_ranks_under_view_layer() {
    let dir = tempfile::tempdir().unwrap();
    let ours = render(dir.path(), "l.exr", &[]);
    let blender = render(dir.path(), "b.exr", &["--layout", "blender"]);
    for kind in ["CryptoObject", "CryptoMaterial"] {
        assert_eq!(
            ranks(&ours, kind),
            ranks(&blender, &format!("ViewLayer.{kind}"))
        );
    }
    let name = text_attribute(&blender, &format!("cryptomatte/{BLENDER_OBJECT_KEY}/name"));
    assert_eq!(name.as_deref(), Some("ViewLayer.CryptoObject"));
}

#[test]
fn obj_materials_are_named_by_their_mtl() {
    let dir = tempfile::tempdir().unwrap();
    let obj = common::files::root().join("assets/illum_modes.obj");
    let o = lumis(
        dir.path(),
        &[
            "render",
            obj.to_str().unwrap(),
            "-o",
            "m.exr",
            "--cryptomatte",
            "--quick",
            "--quiet",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let names: Vec<String> = manifest(&read_exr(&dir.path().join("m.exr")), MATERIAL_KEY)
        .into_keys()
        .collect();
    let want: Vec<String> = (0..10).map(|i| format!("mode{i}")).collect();
    assert_eq!(names, want);
}
