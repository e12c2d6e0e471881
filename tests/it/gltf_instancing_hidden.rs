//! Zero scales in glTF placements, which the specification allows (files hide a mesh so): an
//! `EXT_mesh_gpu_instancing` entry or a node sharing a mesh with a singular transform loads,
//! keeps its objects, and shows what the flattened scene shows: nothing where the scale is
//! zero on two or three axes, a flat copy (no instance) where it is zero on one.

use serde_json::json;

use crate::common;
use crate::gltf_instancing_bad::{add_accessor, original, swarm_attributes, write_beside_buffer};

use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::film::Film;
use lumis_core::scene::Scene;
use lumis_io::formats::{self, LoadOptions};

/// The assets' orthographic camera spans x in [-8, 8], y in [-4, 4]: 20 pixels a unit.
const SIZE: (u32, u32) = (320, 160);

/// `gpu_instancing.gltf` with the swarm's entry 3 scaled to nothing, entry 5 flattened onto
/// its z = 0 plane (facing the camera) and entry 7 onto its x = 0 plane (edge-on), and the
/// flock node placing the shared mesh a second way scaled to zero on every axis; loaded
/// instanced and flattened.
fn load_both() -> (Scene, Scene) {
    let mut doc = original();
    let mut scales: Vec<f32> = (0..50)
        .flat_map(|i| [0.3 + 0.05 * (i % 3) as f32; 3])
        .collect();
    scales[3 * 3..3 * 3 + 3].copy_from_slice(&[0.0; 3]);
    scales[5 * 3 + 2] = 0.0;
    scales[7 * 3] = 0.0;
    let a = add_accessor(&mut doc, "VEC3", &scales, false);
    swarm_attributes(&mut doc)["SCALE"] = json!(a);
    // A fourth node sharing the mesh (no extension), at the origin, scaled to nothing.
    let nodes = doc["nodes"].as_array_mut().unwrap();
    nodes.push(json!({"name": "vanished", "mesh": 0, "scale": [0.0, 0.0, 0.0]}));
    let node = nodes.len() - 1;
    doc["scenes"][0]["nodes"]
        .as_array_mut()
        .unwrap()
        .push(json!(node));

    let dir = tempfile::tempdir().unwrap();
    let file = write_beside_buffer(&doc, dir.path(), "hidden.gltf");
    let load = |flatten_instances| {
        let options = LoadOptions {
            flatten_instances,
            ..LoadOptions::default()
        };
        formats::load_with(&file, &options).unwrap_or_else(|e| panic!("{e:#}"))
    };
    (load(false), load(true))
}

fn render(scene: &Scene) -> Film {
    common::render::film(
        scene.clone(),
        SIZE,
        AccelKind::Sah,
        &BuildOptions::default(),
    )
}

/// The pixel at world point (x, y) on the camera's plane.
fn pixel(x: f32, y: f32) -> usize {
    let col = ((x + 8.0) / 16.0 * SIZE.0 as f32).floor() as usize;
    let row = ((4.0 - y) / 8.0 * SIZE.1 as f32).floor() as usize;
    row * SIZE.0 as usize + col
}

/// The centre of the swarm's entry `i`.
fn swarm(i: usize) -> (f32, f32) {
    (-6.75 + 1.5 * (i % 10) as f32, 3.2 - 0.8 * (i / 10) as f32)
}

fn object_named(scene: &Scene, name: &str) -> i32 {
    scene.objects().iter().position(|o| o.name == name).unwrap() as i32
}

#[test]
fn zero_scales_load_and_show_what_the_flattened_scene_shows() {
    let (inst, flat) = load_both();
    // Every placement keeps its objects, named and ordered as flattened.
    let names = |s: &Scene| -> Vec<String> { s.objects().iter().map(|o| o.name.clone()).collect() };
    assert_eq!(names(&inst), names(&flat));
    assert_eq!(inst.objects().len(), 118);
    // 58 placements of before, one more node, four of them singular: no instances.
    assert_eq!(inst.geometry().instances().len(), 59 - 4);
    // Only the copies flattened onto a plane hold triangles; the hidden ones hold none.
    let copied: usize = inst
        .geometry()
        .meshes()
        .iter()
        .map(|m| m.triangle_count())
        .sum();
    let mesh: usize =
        flat.geometry().meshes()[0].triangle_count() + flat.geometry().meshes()[1].triangle_count();
    assert_eq!(
        copied,
        2 * mesh,
        "entries 5 and 7 copied, 3 and `vanished` not"
    );

    let (fi, ff) = (render(&inst), render(&flat));
    for (film, scene, mode) in [(&fi, &inst, "instanced"), (&ff, &flat, "flattened")] {
        let ids: Vec<i32> = film.aov().iter().map(|a| a.object_id).collect();
        // Hidden: seen nowhere. Edge-on to the camera: seen nowhere either.
        for hidden in [
            "swarm/3/0",
            "swarm/3/1",
            "vanished/0",
            "vanished/1",
            "swarm/7/0",
        ] {
            let id = object_named(scene, hidden);
            assert!(!ids.contains(&id), "{mode}: {hidden} is seen");
        }
        let (x, y) = swarm(3);
        assert_eq!(ids[pixel(x, y)], -1, "{mode}: background where entry 3 was");
        // Flattened facing the camera: seen at its centre.
        let (x, y) = swarm(5);
        let seen = &scene.objects()[ids[pixel(x, y)] as usize].name;
        assert!(seen.starts_with("swarm/5/"), "{mode}: {seen} at entry 5");
        assert!(
            film.rgba()[pixel(x, y)].max_element() > 0.05,
            "{mode}: entry 5 is lit"
        );
    }
    // The flat copy is no instance; its neighbour is.
    let at = |i: usize| fi.aov()[pixel(swarm(i).0, swarm(i).1)].instance_id;
    assert_eq!(at(5), -1);
    assert!(at(4) >= 0 && at(6) >= 0);
    // Pixel for pixel, the two modes agree on what is where: the flat copy is the same
    // triangles, transformed the same way.
    let differ = fi
        .aov()
        .iter()
        .zip(ff.aov())
        .filter(|(a, b)| a.object_id != b.object_id)
        .count();
    assert!(
        differ * 200 <= fi.aov().len(),
        "{differ} pixels see other objects"
    );
}
