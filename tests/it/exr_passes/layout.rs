//! `--layout blender`: every channel gets the name Blender's multilayer EXR gives that pass
//! (`ViewLayer.<Pass>.<channel>`, as Blender's render_result names them), values unchanged.

use exr::prelude::AttributeValue;

use crate::common::exr::{FlatImage, channel};
use crate::exr_passes::{CAMERA, H, W, names, render};

/// The Blender name of each lumis channel, written out here from Blender's pass names
/// (`Combined` RGBA, `Depth` Z, `Normal` XYZ, `IndexOB` X, `DiffCol` RGB, `Position` XYZ,
/// `UV` UVA, Cryptomatte `<layer>.<type>NN` RGBA), not from lumis's table.
fn blender_name(lumis: &str) -> String {
    let pass = match lumis {
        "R" | "G" | "B" | "A" => format!("Combined.{lumis}"),
        "Z" => "Depth.Z".into(),
        "id.object" => "IndexOB.X".into(),
        "id.prim" => "IndexPrim.X".into(),
        _ => {
            let (layer, c) = lumis.split_once('.').expect("layer.channel");
            let layer = match layer {
                "N" => "Normal",
                "albedo" => "DiffCol",
                "P" => "Position",
                "uv" => "UV",
                crypto if crypto.starts_with("Crypto") => crypto,
                other => panic!("no Blender name known for {other}"),
            };
            format!("{layer}.{c}")
        }
    };
    format!("ViewLayer.{pass}")
}

const SCENE_TAIL: &str = "
[materials.red]
diffuse = [0.7, 0.2, 0.1]

[[sphere]]
name = \"ball\"
center = [-0.6, 0.0, 0.0]
radius = 1.0
material = \"red\"

[[sphere]]
name = \"moon\"
center = [1.2, 0.3, 0.5]
radius = 0.5

[[light]]
type = \"directional\"
direction = [0.0, -1.0, -1.0]
intensity = 2.0
";

/// The `name` values of the Cryptomatte metadata, sorted.
fn crypto_names(image: &FlatImage) -> Vec<String> {
    let mut v: Vec<String> = image.layer_data[0]
        .attributes
        .other
        .iter()
        .filter(|(k, _)| k.to_string().ends_with("/name"))
        .map(|(_, v)| match v {
            AttributeValue::Text(t) => t.to_string(),
            other => panic!("{other:?}"),
        })
        .collect();
    v.sort();
    v
}

#[test]
fn blender_layout_renames_every_channel_and_keeps_every_value() {
    let dir = tempfile::tempdir().unwrap();
    let scene = format!("{CAMERA}{SCENE_TAIL}");
    let passes = ["--aov", "albedo,position,uv", "--cryptomatte", "--spp", "2"];
    for (extra, tag) in [(&[][..], "plain"), (&passes[..], "passes")] {
        let lumis = render(dir.path(), "s.toml", &scene, "l.exr", extra);
        let blender = render(
            dir.path(),
            "s.toml",
            &scene,
            "b.exr",
            &[extra, &["--layout", "blender"]].concat(),
        );
        let mut want: Vec<String> = names(&lumis).iter().map(|n| blender_name(n)).collect();
        if tag == "passes" {
            // Blender's UV pass has a third channel, A: 1 where a surface was hit.
            want.push("ViewLayer.UV.A".into());
        }
        want.sort();
        assert_eq!(names(&blender), want, "{tag}");
        for name in names(&lumis) {
            let (a, b) = (
                channel(&lumis, &name),
                channel(&blender, &blender_name(&name)),
            );
            assert!(
                a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()),
                "{tag}: {name} differs"
            );
        }
        if tag == "plain" {
            assert_eq!(names(&lumis).len(), 10);
            continue;
        }
        let (id, uv_a) = (
            channel(&lumis, "id.object"),
            channel(&blender, "ViewLayer.UV.A"),
        );
        assert!(id.iter().any(|&o| o < 0.0) && id.iter().any(|&o| o >= 0.0));
        for i in 0..W * H {
            assert_eq!(uv_a[i], if id[i] >= 0.0 { 1.0 } else { 0.0 }, "pixel {i}");
        }
        // The Cryptomatte metadata names the layers by their channel prefix.
        assert_eq!(crypto_names(&lumis), ["CryptoMaterial", "CryptoObject"]);
        assert_eq!(
            crypto_names(&blender),
            ["ViewLayer.CryptoMaterial", "ViewLayer.CryptoObject"]
        );
    }
}
