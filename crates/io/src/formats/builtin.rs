//! The default scene, compiled into the binary with its assets so it renders from any
//! working directory: `scenes/default.toml` and the OBJ files it references.

use std::path::Path;

use super::SceneError;
use super::toml::{Override, load_toml_str_at};
use lumis_core::scene::Scene;

/// Where the embedded default scene claims to live (in messages and for resolving its assets).
const DEFAULT_SCENE_PATH: &str = "scenes/default.toml";

/// The default scene's text.
const DEFAULT_SCENE: &str = include_str!("../../../../scenes/default.toml");

/// Assets the default scene may reference, by file name.
const ASSETS: &[(&str, &[u8])] = &[("knot.obj", include_bytes!("../../../../assets/knot.obj"))];

/// The scene `lumis` renders when given no file: `scenes/default.toml` with its meshes, all
/// embedded at compile time. An error here is a bug in the shipped scene (a test guards it).
pub fn default_scene() -> Result<Scene, SceneError> {
    default_scene_with(&[])
}

/// [`default_scene`] with `-D` overrides: it is a TOML scene, so every key can be overridden.
pub fn default_scene_with(overrides: &[Override]) -> Result<Scene, SceneError> {
    default_scene_at(overrides, None)
}

/// [`default_scene_with`] at `frame` (`--frame`): the default scene is a still, so any frame
/// is an error, unless a `-D animation.frames=N` made it a (motionless) animation.
pub fn default_scene_at(overrides: &[Override], frame: Option<u32>) -> Result<Scene, SceneError> {
    // The embedded assets by name; any other file (an environment map given with --env or
    // -D environment.file) from disk, relative paths starting in scenes/ as for the file.
    let resolver = |path: &Path| {
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        match ASSETS.iter().find(|(asset, _)| *asset == name) {
            Some((_, bytes)) => Ok(bytes.to_vec()),
            None => super::read_file_bytes(path),
        }
    };
    load_toml_str_at(
        DEFAULT_SCENE,
        Path::new(DEFAULT_SCENE_PATH),
        &resolver,
        overrides,
        frame,
    )
}
