//! Every file format lumis reads, behind one entry point: [`load`] picks the reader from the
//! file extension and returns a [`Scene`] or a [`SceneError`] naming the file and the line or
//! element at fault.
//!
//! - [`toml`]: lumis's own scene description;
//! - [`scn`]: the paper's `.scn` scenes and their `.m` meshes;
//! - [`obj`]: Wavefront OBJ with MTL materials (also as meshes inside TOML scenes);
//! - [`gltf`]: glTF 2.0 (`.gltf`, `.glb`);
//! - [`builtin`]: the default scene compiled into the binary.
//!
//! Readers never open files themselves: everything a scene references comes through a
//! [`Resolver`], so the embedded default scene and tests can supply bytes from memory.

pub mod builtin;
pub mod environment;
mod error;
pub mod gltf;
pub mod images;
pub mod obj;
mod resolver;
pub mod scn;
pub mod toml;

pub use builtin::{default_scene, default_scene_at, default_scene_with};
pub use error::SceneError;
pub use resolver::{Resolver, read_file, read_file_bytes, read_text};
pub use toml::Override;

use std::path::Path;

use lumis_core::scene::{Scene, UpAxis};

/// Choices a file leaves to the caller: `scene` and `camera` only exist in glTF files, `up`
/// and `auto_camera` apply to OBJ files too, `frame` to TOML scenes with an `[animation]`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// Index of the scene to render (`--gltf-scene`); `None`: the file's default scene.
    pub scene: Option<usize>,
    /// Which camera to look through (`--camera`): the N-th camera node met depth first in the
    /// scene's hierarchy; `None`: the first, or the automatic framing camera when there is none.
    pub camera: Option<usize>,
    /// Which model axis is up (`--up`); the model is turned to lumis's Y-up world before the
    /// automatic camera and light rig are placed. glTF is Y-up by specification.
    pub up: UpAxis,
    /// Ignore the file's cameras and use the automatic framing camera (`--auto-camera`).
    pub auto_camera: bool,
    /// The frame of a TOML scene's `[animation]` to pose it at (`--frame`); `None`: frame 0
    /// of an animated scene. Other formats have no frames (glTF animations are not read).
    pub frame: Option<u32>,
    /// Draw every placement of a mesh as its own world-space copy (`--flatten-instances`)
    /// instead of making meshes placed twice or more, and `EXT_mesh_gpu_instancing` nodes,
    /// instances of one prototype. Only glTF files make instances; the other formats are
    /// flat already and read it as a no-op.
    pub flatten_instances: bool,
}

impl LoadOptions {
    /// Whether only `frame` (or nothing) is chosen: what a TOML scene accepts.
    fn is_frame_only(&self) -> bool {
        Self {
            frame: None,
            ..self.without_flattening()
        } == Self::default()
    }

    /// These options less `flatten_instances`, which every format accepts.
    fn without_flattening(&self) -> Self {
        Self {
            flatten_instances: false,
            ..*self
        }
    }
}

/// Loads a scene file, choosing the format by extension: `.toml` is a scene description,
/// `.scn` the paper's format, `.obj` a bare model shown with an automatic camera, a default
/// two-light rig and its MTL materials (a grey default for objects without one),
/// `.gltf`/`.glb` a glTF 2.0 scene (its default scene and first camera).
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    load_with(path, &LoadOptions::default())
}

/// [`load`] with the choices model files offer: scene and camera (glTF only), up axis and
/// automatic camera (glTF and OBJ); asking for them in any other format is an error.
pub fn load_with(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    load_with_overrides(path, options, &[])
}

/// [`load_with`] plus `-D` overrides, applied in order: in a TOML scene to the document
/// before it is checked (any key of the schema); in every other format only `render.*` and
/// `environment.*` keys, through the same schemas, over what the file set (other keys are
/// refused before the file is read).
pub fn load_with_overrides(
    path: &Path,
    options: &LoadOptions,
    overrides: &[Override],
) -> Result<Scene, SceneError> {
    let is_toml = extension(path).as_deref() == Some("toml");
    if !is_toml && let Some(o) = overrides.iter().find(|o| !o.is_render()) {
        return Err(toml::refuse_non_render(path, o));
    }
    if !is_toml && let Some(f) = options.frame {
        return Err(SceneError::invalid(
            path,
            format!("--frame {f}"),
            "only TOML scenes have frames (an [animation] table); glTF animations are not \
             read, and OBJ and .scn files have none",
        ));
    }
    let mut scene = if is_toml && options.is_frame_only() {
        toml::load_toml_file_at(path, overrides, options.frame)?
    } else {
        load_by_extension(path, options)?
    };
    if !is_toml {
        toml::apply_render_overrides(&mut scene, overrides, path)?;
    }
    // Every format's settings meet the same limits (TOML and .scn also check them where they
    // can name the element or line).
    scene
        .settings()
        .validate()
        .map_err(|e| SceneError::invalid(path, "render settings", e.to_string()))?;
    Ok(scene)
}

/// The loader of `path`'s format.
fn load_by_extension(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    match extension(path).as_deref() {
        Some("gltf" | "glb") => gltf::load_gltf_file(path, options),
        Some("obj") if options.scene.is_none() && options.camera.is_none() => {
            obj::load_obj_scene(path, options)
        }
        _ if options.without_flattening() != LoadOptions::default() => Err(SceneError::invalid(
            path,
            "options",
            "a scene or camera index (--gltf-scene, --camera) applies to glTF files only, an \
             up axis or the automatic camera (--up, --auto-camera) to glTF and OBJ files only",
        )),
        Some("toml") => toml::load_toml_file(path),
        Some("scn") => scn::load_scn_file(path),
        _ => Err(SceneError::UnknownFormat {
            path: path.to_path_buf(),
        }),
    }
}

/// Whether `path` names a bare model (glTF or OBJ, by extension, in any case): a file whose
/// lights say nothing about a sensible brightness, so a render exposes it automatically
/// unless told otherwise ([`crate::request::exposure_to_apply`]).
pub fn is_model_file(path: &Path) -> bool {
    matches!(extension(path).as_deref(), Some("gltf" | "glb" | "obj"))
}

/// The file extension, lower case.
fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}
