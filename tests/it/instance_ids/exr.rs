//! The centre-ray AOV's `id.instance`: its values at pixels of each instance, written to the
//! EXR (lumis and Blender names) and read back, kept bit for bit by the farm merge; the
//! Cryptomatte object names of instances; and no such channel for a scene without instances.

use super::{instance_of_name, scene};
use crate::common::cli::assert_ok;
use crate::common::exr::{channel, read_exr as read_flat};
use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::film::{DisplayTransform, Film, TileSpec, Tonemap};
use lumis_core::render::{RenderOptions, render};
use lumis_core::scene::World;
use lumis_io::farm::merge_tiles;
use lumis_io::output::{
    AovLayers, ChannelLayout, Develop, ExrCamera, ExrMetadata, RenderIdentity, TileHeader, develop,
    read_exr,
};
use std::path::{Path, PathBuf};
use std::process::Command;

const W: u32 = 64;
const H: u32 = 32;

fn world() -> World {
    World::build(scene(W, H), AccelKind::Sah, &BuildOptions::default())
}

/// The film of `world` (or of `tile` of it), with two Cryptomatte ranks a pixel.
fn film(world: &World, tile: Option<TileSpec>) -> Film {
    let opts = RenderOptions {
        seed: 7,
        threads: Some(2),
        cryptomatte: Some(2),
        window: tile.map(|t| t.window(W, H).unwrap()),
        ..RenderOptions::default()
    };
    render(world, &opts).unwrap().film
}

fn meta(layout: ChannelLayout) -> ExrMetadata {
    ExrMetadata {
        float_rgba: true,
        aov_layers: AovLayers {
            instance: true,
            ..AovLayers::default()
        },
        layout,
        identity: Some(RenderIdentity {
            scene_hash: "instance ids".into(),
            seed: 7,
            settings: r#"{"render": {"width": 64, "height": 32}}"#.into(),
            replay: None,
        }),
        ..ExrMetadata::default()
    }
}

const HOW: Develop = Develop {
    exposure: Some(0.0),
    tonemap: Tonemap::None,
    display: DisplayTransform::Srgb,
};

/// `film` developed to `path`; returns the bytes written.
fn write(film: &mut Film, world: &World, path: &Path, meta: &mut ExrMetadata) -> Vec<u8> {
    let camera = ExrCamera::new(world.scene().camera(), W, H);
    let developed = develop(film, &camera, &[path], &HOW, meta).unwrap();
    let bytes = developed.images[0].1.clone();
    std::fs::write(path, &bytes).unwrap();
    bytes
}

#[test]
fn pixels_of_each_instance_carry_its_index() {
    let world = world();
    let film = film(&world, None);
    let objects = world.scene().objects();
    let mut seen = [0usize; 4];
    for a in film.aov() {
        if a.object_id < 0 {
            assert_eq!(a.instance_id, -1, "a miss has no instance");
            continue;
        }
        let name = &objects[a.object_id as usize].name;
        let want = instance_of_name(name).map_or(-1, |k| k as i32);
        assert_eq!(a.instance_id, want, "pixel on {name}");
        seen[(want + 1) as usize] += 1;
    }
    // The ground and each of the three instances fill many pixels.
    assert!(seen.iter().all(|&n| n > 20), "{seen:?}");
    // The image centre shows copy1's ball, the left and right thirds copy0's and copy2's.
    assert_eq!(film.pixel_aov(W / 2, H / 2).instance_id, 1);
    let left = film.pixel_aov(W / 2 - 13, H / 2);
    let right = film.pixel_aov(W / 2 + 13, H / 2);
    assert_eq!((left.instance_id, right.instance_id), (0, 2));
    assert_eq!(film.pixel_aov(0, 0).instance_id, -1, "a ground corner");
}

#[test]
fn id_instance_is_written_and_read_back_in_both_layouts() {
    let dir = tempfile::tempdir().unwrap();
    let world = world();
    let rendered = film(&world, None);
    for (layout, name) in [
        (ChannelLayout::Lumis, "id.instance"),
        (ChannelLayout::Blender, "ViewLayer.IndexInstance.X"),
    ] {
        let path = dir.path().join(format!("{layout:?}.exr"));
        let mut f = rendered.clone();
        let mut m = meta(layout);
        let bytes = write(&mut f, &world, &path, &mut m);
        let stored = channel(&read_flat(&path), name);
        let want: Vec<f32> = rendered
            .aov()
            .iter()
            .map(|a| a.instance_id as f32)
            .collect();
        assert_eq!(stored, want, "{layout:?}");
        // lumis's reader gives the film back, and writing it again gives the same bytes.
        let mut back = read_exr(&path).unwrap();
        assert!(back.meta.aov_layers.instance, "{layout:?}");
        // The ids and depth come back (albedo, position and uv were not asked for).
        let ids = |f: &Film| -> Vec<(i32, i32, i32, u32)> {
            f.aov()
                .iter()
                .map(|a| (a.prim_id, a.object_id, a.instance_id, a.depth.to_bits()))
                .collect()
        };
        assert!(ids(&back.film) == ids(&rendered), "{layout:?}");
        let again = dir.path().join(format!("{layout:?}-again.exr"));
        assert_eq!(write(&mut back.film, &world, &again, &mut back.meta), bytes);
    }
}

#[test]
fn the_merge_keeps_id_instance_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let world = world();
    let mut single = film(&world, None);
    let whole = write(
        &mut single,
        &world,
        &dir.path().join("whole.exr"),
        &mut meta(ChannelLayout::Lumis),
    );
    let tiles: Vec<PathBuf> = TileSpec::all(3)
        .map(|spec| {
            let path = dir.path().join(format!("tile{}.exr", spec.index));
            let mut m = ExrMetadata {
                tile: Some(TileHeader {
                    spec,
                    exposure: Some(0.0),
                    display: DisplayTransform::Srgb,
                }),
                ..meta(ChannelLayout::Lumis)
            };
            write(&mut film(&world, Some(spec)), &world, &path, &mut m);
            path
        })
        .collect();
    let mut merged = merge_tiles(&tiles).unwrap();
    let out = dir.path().join("merged.exr");
    let developed = merged.develop(&[&out], Tonemap::None, None).unwrap();
    assert_eq!(
        developed.images[0].1, whole,
        "the merge is the single render's file"
    );
    std::fs::write(&out, &developed.images[0].1).unwrap();
    let ids = channel(&read_flat(&out), "id.instance");
    assert!(
        (0..3).all(|k| ids.contains(&(k as f32))),
        "every instance in the merge"
    );
}

#[test]
fn cryptomatte_names_each_instances_objects() {
    let world = world();
    let film = film(&world, None);
    let layer = film
        .crypto()
        .iter()
        .find(|l| l.name() == "CryptoObject")
        .expect("an object layer");
    let manifest = layer.manifest();
    let names: Vec<String> = manifest.keys().cloned().collect();
    let mut want = vec!["ground".to_string()];
    for k in 0..3 {
        want.extend([format!("copy{k}/ball"), format!("copy{k}/tile")]);
    }
    want.sort_unstable();
    assert_eq!(names, want);
    // Where a pixel and its eight neighbours show one object, its matte is that object's
    // whole, under the instance's own name.
    let objects = world.scene().objects();
    let (w, h) = (W as i32, H as i32);
    let mut checked = [0usize; 3];
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let at = |dx: i32, dy: i32| film.pixel_aov((x + dx) as u32, (y + dy) as u32);
            let centre = at(0, 0);
            let interior =
                (-1..=1).all(|dy| (-1..=1).all(|dx| at(dx, dy).object_id == centre.object_id));
            if !interior || centre.instance_id < 0 {
                continue;
            }
            let name = &objects[centre.object_id as usize].name;
            let rank = layer.pixel((y * w + x) as usize)[0];
            assert_eq!(rank.id, manifest[name], "pixel ({x}, {y}) on {name}");
            assert_eq!(rank.coverage, 1.0, "pixel ({x}, {y}) on {name}");
            assert!(name.starts_with(&format!("copy{}/", centre.instance_id)));
            checked[centre.instance_id as usize] += 1;
        }
    }
    assert!(checked.iter().all(|&n| n > 4), "{checked:?}");
}

#[test]
fn a_scene_without_instances_gets_no_instance_channel() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, super::hits::PLAIN).unwrap();
    for layout in ["lumis", "blender"] {
        let out = dir.path().join(format!("{layout}.exr"));
        let run = Command::new(env!("CARGO_BIN_EXE_lumis"))
            .arg("render")
            .arg(&scene)
            .args(["--width", "8", "--height", "4", "--spp", "1", "--quiet"])
            .args(["--layout", layout, "-o"])
            .arg(&out)
            .output()
            .unwrap();
        assert_ok(&run);
        let image = read_flat(&out);
        let names = crate::common::exr::channel_names(&image);
        assert!(
            names
                .iter()
                .any(|n| n.contains("id.object") || n.contains("IndexOB"))
        );
        assert!(
            !names
                .iter()
                .any(|n| n.contains("instance") || n.contains("Instance")),
            "{names:?}"
        );
        assert!(!read_exr(&out).unwrap().meta.aov_layers.instance);
    }
}
