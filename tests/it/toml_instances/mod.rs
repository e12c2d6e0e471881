//! TOML `[[instance]]`: a `[[mesh]]` or `[[sphere]]` drawn only where instances place it, by
//! one placement or arrays of them, moved by `-D` and by `[[animation.instance]]` keys; bad
//! tables are refused naming the table and the key.

mod animation;
mod errors;
mod flattened;
mod placements;

use std::path::Path;

use lumis_core::accel::{AccelKind, BuildOptions, TraversalStats};
use lumis_core::math::{Ray, Vec3};
use lumis_core::scene::{Interaction, Scene, World};
use lumis_io::formats::toml::load_toml_str_at;
use lumis_io::formats::{Override, SceneError, read_file_bytes};

/// The scene `text` (as `scene.toml`) with `-D` overrides `defines`, at `frame`.
fn load_at(text: &str, defines: &[&str], frame: Option<u32>) -> Result<Scene, SceneError> {
    let overrides: Vec<Override> = defines.iter().map(|d| d.parse().unwrap()).collect();
    load_toml_str_at(
        text,
        Path::new("scene.toml"),
        &read_file_bytes,
        &overrides,
        frame,
    )
}

/// The scene `text`; a load error fails the test with its message.
fn load(text: &str) -> Scene {
    load_at(text, &[], None).unwrap_or_else(|e| panic!("{e}"))
}

/// The message of the error loading `text` with `defines`.
fn error(text: &str, defines: &[&str]) -> String {
    match load_at(text, defines, None) {
        Ok(_) => panic!("loaded, expected an error:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// The first hit of the ray from `origin` along `dir`, with the name of the object hit.
fn hit(world: &World, origin: Vec3, dir: Vec3) -> Option<(Interaction, String)> {
    let i = world.intersect(&Ray::new(origin, dir), &mut TraversalStats::default())?;
    let name = world.scene().objects()[i.object as usize].name.clone();
    Some((i, name))
}

fn world(scene: Scene) -> World {
    World::build(scene, AccelKind::Sah, &BuildOptions::default())
}

/// A repository file's absolute path, for `file = ...` in a scene text.
fn asset(p: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(p)
        .to_string_lossy()
        .replace('\\', "/")
}
