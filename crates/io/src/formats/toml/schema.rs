//! The serde schema of a TOML scene file: what may appear where, and with which type.
//! Unknown keys are errors, so a typo never passes silently. Values are checked later, in
//! [`super`], where errors can name the element.

use std::collections::BTreeMap;

use serde::Deserialize;

/// A whole scene file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SceneDoc {
    #[serde(default)]
    pub render: RenderDoc,
    pub camera: Option<CameraDoc>,
    #[serde(default)]
    pub materials: BTreeMap<String, MaterialDoc>,
    #[serde(default)]
    pub light: Vec<LightDoc>,
    #[serde(default)]
    pub sphere: Vec<SphereDoc>,
    #[serde(default)]
    pub mesh: Vec<MeshDoc>,
    #[serde(default)]
    pub instance: Vec<InstanceDoc>,
    pub animation: Option<AnimationDoc>,
    pub environment: Option<EnvironmentDoc>,
}

/// `[environment]` (`environment.rs`).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct EnvironmentDoc {
    pub file: Option<String>,
    pub rotation: Option<f32>,
    pub intensity: Option<f32>,
    pub sun: Option<bool>,
}

/// `[render]`: every key optional, defaults from `Settings::default()`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RenderDoc {
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub spp: Option<u32>,
    pub max_depth: Option<u32>,
    pub ambient: Option<[f32; 3]>,
    pub background: Option<[f32; 3]>,
    pub exposure: Option<f32>,
    pub precision: Option<String>,
    pub offset: Option<String>,
    pub epsilon: Option<f32>,
    pub cutoff: Option<f32>,
    pub display: Option<String>,
    pub adaptive: Option<f32>,
}

/// `[camera]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraDoc {
    /// `"perspective"` (default) or `"orthographic"`.
    #[serde(rename = "type")]
    pub kind: Option<String>,
    /// Orthographic only: the world-space height the image spans.
    pub height: Option<f32>,
    pub position: [f32; 3],
    pub look_at: [f32; 3],
    pub up: Option<[f32; 3]>,
    pub fov: Option<f32>,
    pub aperture: Option<f32>,
    pub focus_distance: Option<f32>,
}

/// `[materials.NAME]`: every key optional, defaults from `Material::default()`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MaterialDoc {
    pub diffuse: Option<[f32; 3]>,
    pub specular: Option<[f32; 3]>,
    pub shininess: Option<f32>,
    pub reflectivity: Option<f32>,
    pub transmission: Option<f32>,
    pub ior: Option<f32>,
    pub emission: Option<[f32; 3]>,
    /// Cycles' shadow catcher: only the shadow the surface receives is rendered.
    pub shadow_catcher: Option<bool>,
}

/// `[[light]]`. One flat table (not a serde-tagged enum) so errors keep exact line numbers;
/// which keys each `type` needs is checked in [`super`].
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LightDoc {
    /// Names the light's pass (`light.<name>`); default `light<index>`.
    pub name: Option<String>,
    #[serde(rename = "type")]
    pub kind: LightKind,
    pub position: Option<[f32; 3]>,
    pub direction: Option<[f32; 3]>,
    pub color: Option<[f32; 3]>,
    pub intensity: f32,
}

/// The `type` of a light.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(super) enum LightKind {
    Point,
    Directional,
}

/// `[[sphere]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SphereDoc {
    pub name: Option<String>,
    pub center: [f32; 3],
    pub radius: f32,
    pub material: Option<String>,
}

/// `[[mesh]]`: an OBJ `file` or inline `positions` + `indices`, then a transform.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MeshDoc {
    pub name: Option<String>,
    pub material: Option<String>,
    pub file: Option<String>,
    pub positions: Option<Vec<[f32; 3]>>,
    pub indices: Option<Vec<[u32; 3]>>,
    pub normals: Option<Vec<[f32; 3]>>,
    pub translate: Option<[f32; 3]>,
    pub rotate: Option<[f32; 3]>,
    pub scale: Option<Scale>,
    pub smooth: Option<bool>,
}

/// `scale = 2.0` or `scale = [1.0, 2.0, 1.0]`.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(untagged, expecting = "a number or an array [x, y, z]")]
pub(super) enum Scale {
    Uniform(f32),
    PerAxis([f32; 3]),
}

/// `[[instance]]` (`instance.rs`): the `[[mesh]]` or `[[sphere]]` named `of`, placed by one
/// placement or by arrays of them. Values are `f32` as a mesh's transform (so keys pose them
/// exactly); the placement is computed from them in `f64`. `matrix` is `f64`: its entries
/// (sines, cosines) are worth the digits.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct InstanceDoc {
    pub of: String,
    pub name: Option<String>,
    pub translate: Option<[f32; 3]>,
    pub rotate: Option<[f32; 3]>,
    pub scale: Option<Scale>,
    pub matrix: Option<Vec<f64>>,
    pub translations: Option<Vec<[f32; 3]>>,
    pub rotations: Option<Vec<[f32; 3]>>,
    pub scales: Option<Vec<Scale>>,
}

/// `[animation]`: the frame range and rate, and the keys of what moves.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct AnimationDoc {
    /// How many frames, numbered from 0.
    pub frames: u32,
    pub fps: Option<FpsDoc>,
    /// Every key's interpolation unless the key gives its own (default linear).
    pub interpolation: Option<InterpolationDoc>,
    #[serde(default)]
    pub camera: Vec<CameraKeyDoc>,
    #[serde(default)]
    pub sphere: Vec<SphereKeyDoc>,
    #[serde(default)]
    pub mesh: Vec<MeshKeyDoc>,
    /// `[[animation.instance]]`: the same fields as a mesh key, on a named `[[instance]]`.
    #[serde(default)]
    pub instance: Vec<MeshKeyDoc>,
}

/// `fps = 24` or `fps = [24000, 1001]` (numerator, denominator).
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(
    untagged,
    expecting = "a whole number of frames per second or [numerator, denominator], e.g. 24 or [24000, 1001]"
)]
pub(super) enum FpsDoc {
    Whole(u32),
    Ratio([u32; 2]),
}

/// A key's `interpolation`.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(super) enum InterpolationDoc {
    Linear,
    Step,
}

/// `[[animation.camera]]`: the `[camera]` keys that can change over time, at one frame.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraKeyDoc {
    pub frame: u32,
    pub interpolation: Option<InterpolationDoc>,
    pub position: Option<[f32; 3]>,
    pub look_at: Option<[f32; 3]>,
    pub up: Option<[f32; 3]>,
    pub fov: Option<f32>,
    pub aperture: Option<f32>,
    pub focus_distance: Option<f32>,
    pub height: Option<f32>,
}

/// `[[animation.sphere]]`: the named `[[sphere]]`'s `center` and `radius` at one frame.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SphereKeyDoc {
    pub name: String,
    pub frame: u32,
    pub interpolation: Option<InterpolationDoc>,
    pub center: Option<[f32; 3]>,
    pub radius: Option<f32>,
}

/// `[[animation.mesh]]` and `[[animation.instance]]`: the `translate` and `rotate` of the
/// named `[[mesh]]` or `[[instance]]` at one frame.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MeshKeyDoc {
    pub name: String,
    pub frame: u32,
    pub interpolation: Option<InterpolationDoc>,
    pub translate: Option<[f32; 3]>,
    pub rotate: Option<[f32; 3]>,
}
