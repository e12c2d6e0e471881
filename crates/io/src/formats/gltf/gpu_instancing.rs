//! `EXT_mesh_gpu_instancing`: a node whose mesh is drawn once per element of its TRANSLATION,
//! ROTATION and SCALE accessors, at node world x T_i x R_i x S_i, and not at the node itself.
//!
//! TRANSLATION and SCALE are float VEC3; ROTATION is a VEC4 quaternion (x, y, z, w) of floats
//! or of normalized signed bytes or shorts, dequantised by the specification's
//! `max(c / 127, -1)` / `max(c / 32767, -1)`. An absent attribute is the identity, but at least
//! one must be present and all present ones must have the same count.
//!
//! Rotations are normalised, not required to be exactly unit: quantisation leaves |q| off by
//! up to about 4e-3 for bytes (half a step, 1/254, on each of four components), 2e-5 for
//! shorts. A quaternion further from unit length than its encoding explains (1e-3 for floats
//! and shorts, 2e-2 for bytes) is refused: it is a wrong accessor, not rounding, and
//! normalising it would hide that. A zero scale is allowed (the specification lets files hide
//! a mesh so): the scene builder draws such an entry flattened, or not at all when nothing of
//! it is left to hit (`lumis_core::scene::SceneBuilder::add_instance`).

use std::path::Path;

use glam::{DAffine3, DQuat, DVec3};
use gltf::accessor::{DataType, Dimensions};
use serde_json::Value;

use super::super::SceneError;
use super::accessor::{self, Allowed};

/// The extension's name, as in `extensionsUsed` and on nodes.
pub(super) const NAME: &str = "EXT_mesh_gpu_instancing";

/// The instance transforms (node space, T x R x S) of `node`'s `EXT_mesh_gpu_instancing`, in
/// accessor order; `None` when the node does not use the extension.
pub(super) fn local_transforms(
    node: &gltf::Node,
    doc: &gltf::Document,
    buffers: &[Vec<u8>],
    origin: &Path,
) -> Result<Option<Vec<DAffine3>>, SceneError> {
    let Some(ext) = node.extension_value(NAME) else {
        return Ok(None);
    };
    let element = format!("nodes[{}].extensions.{NAME}", node.index());
    let err =
        |at: &str, message: String| SceneError::invalid(origin, format!("{element}{at}"), message);
    let attributes = ext
        .get("attributes")
        .and_then(Value::as_object)
        .ok_or_else(|| err("", "has no `attributes` object".into()))?;
    let accessor_of = |key: &str| -> Result<Option<gltf::Accessor>, SceneError> {
        let Some(v) = attributes.get(key) else {
            return Ok(None);
        };
        let at = format!(".attributes.{key}");
        let index = v
            .as_u64()
            .ok_or_else(|| err(&at, format!("is {v}; expected an accessor index")))?;
        let found = usize::try_from(index)
            .ok()
            .and_then(|i| doc.accessors().nth(i));
        found.map(Some).ok_or_else(|| {
            err(
                &at,
                format!(
                    "accessor {index} does not exist (the file has {})",
                    doc.accessors().len()
                ),
            )
        })
    };
    let (t, r, s) = (
        accessor_of("TRANSLATION")?,
        accessor_of("ROTATION")?,
        accessor_of("SCALE")?,
    );
    let count = match [&t, &r, &s].into_iter().flatten().map(|a| a.count()).max() {
        Some(n) => n,
        None => {
            return Err(err(
                ".attributes",
                "has none of TRANSLATION, ROTATION, SCALE".into(),
            ));
        }
    };
    for (key, acc) in [("TRANSLATION", &t), ("ROTATION", &r), ("SCALE", &s)] {
        if let Some(a) = acc
            && a.count() != count
        {
            return Err(err(
                &format!(".attributes.{key}"),
                format!(
                    "accessors[{}] has {} elements; the other attributes have {count} (every \
                     attribute gives one value per instance)",
                    a.index(),
                    a.count()
                ),
            ));
        }
    }
    // Read through the bounded reader: `check_accessors` has already checked each count
    // against the bytes of its buffer view, so `count` is backed by the file.
    let read = |key: &str, acc: &Option<gltf::Accessor>, dims: Dimensions, allowed: Allowed| {
        let at = format!(".attributes.{key}");
        acc.as_ref()
            .map(|a| {
                accessor::read::<4>(a, &[dims], allowed, buffers)
                    .map_err(|m| err(&at, format!("accessors[{}] {m}", a.index())))
            })
            .transpose()
    };
    let translations = read("TRANSLATION", &t, Dimensions::Vec3, Allowed::Float)?;
    let rotations = read("ROTATION", &r, Dimensions::Vec4, Allowed::Rotation)?;
    let scales = read("SCALE", &s, Dimensions::Vec3, Allowed::Float)?;
    // How far from unit length a quaternion may be in its encoding (see the module docs).
    let tolerance = match r.as_ref().map(|a| a.data_type()) {
        Some(DataType::I8) => 2e-2,
        _ => 1e-3,
    };
    let mut out = Vec::with_capacity(count);
    for i in 0..count {
        let vec3 = |v: &[f32; 4]| DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
        let translation = translations.as_ref().map_or(DVec3::ZERO, |v| vec3(&v[i]));
        if !translation.is_finite() {
            return Err(err(
                ".attributes.TRANSLATION",
                format!("instance {i}: translation {translation} is not finite"),
            ));
        }
        let scale = scales.as_ref().map_or(DVec3::ONE, |v| vec3(&v[i]));
        if !scale.is_finite() {
            return Err(err(
                ".attributes.SCALE",
                format!("instance {i}: scale {scale} is not finite"),
            ));
        }
        let rotation = match &rotations {
            None => DQuat::IDENTITY,
            Some(v) => {
                let q = DQuat::from_array(v[i].map(f64::from));
                let length = q.length();
                if !q.is_finite() || (length - 1.0).abs() > tolerance {
                    return Err(err(
                        ".attributes.ROTATION",
                        format!(
                            "instance {i}: quaternion {:?} has length {length}; expected a unit \
                             quaternion (x, y, z, w) within {tolerance}",
                            v[i]
                        ),
                    ));
                }
                q / length
            }
        };
        out.push(DAffine3::from_scale_rotation_translation(
            scale,
            rotation,
            translation,
        ));
    }
    Ok(Some(out))
}
