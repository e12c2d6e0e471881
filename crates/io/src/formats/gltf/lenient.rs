//! Valid glTF that the `gltf` crate would refuse. The crate's schema and validation are
//! stricter than the specification in a few places, and real exporters rely on them:
//!
//! * application-specific vertex attributes (`_BARYCENTRIC`, `_FEATURE_ID_0`: the specification
//!   allows any semantic that starts with `_`) fail validation as `<invalid semantic name>`;
//!   they are removed before the crate sees them, with a warning naming them;
//! * a scene without `nodes` (optional in the specification) fails deserialisation; it is read
//!   as an empty scene;
//! * a `POSITION` accessor without `min`/`max` (required by the specification, omitted by real
//!   files) and a primitive without `POSITION` (allowed: it is not drawn) fail validation; those
//!   two findings are downgraded to warnings. lumis computes bounds from the vertices anyway.
//! * a texture without `source` is allowed through the crate's `allow_empty_texture` feature
//!   (textures.rs warns and leaves it out);
//! * an accessor with neither `bufferView` nor `sparse` (all zeros, by the specification) fails
//!   validation as missing data; it is read as zeros;
//! * a spot light without its `spot` object (whose properties all have defaults) fails
//!   validation; it gets the default cone, with a warning.
//!
//! Every other validation error still refuses the file.

use std::path::Path;

use gltf::Document;
use gltf::json::Root;
use gltf::json::validation::{Error as Finding, Validate};
use serde_json::Value;

use super::super::SceneError;

/// The crate's document model of glTF JSON text `json`, after the repairs in the module docs.
pub(super) fn root(
    json: &[u8],
    path: &Path,
    warnings: &mut Vec<String>,
) -> Result<Root, SceneError> {
    let fail = |e: serde_json::Error| SceneError::Gltf {
        path: path.to_path_buf(),
        message: format!("JSON: {e}"),
    };
    let mut value: Value = serde_json::from_slice(json).map_err(fail)?;
    if repair(&mut value, path, warnings) {
        serde_json::from_value(value).map_err(fail)
    } else {
        // From the text, not the value, so that schema errors keep their line numbers.
        serde_json::from_slice(json).map_err(fail)
    }
}

/// Removes `_` attributes and gives scenes without `nodes` an empty list; true if anything
/// changed.
fn repair(value: &mut Value, path: &Path, warnings: &mut Vec<String>) -> bool {
    let mut changed = false;
    if let Some(scenes) = value.get_mut("scenes").and_then(Value::as_array_mut) {
        for scene in scenes.iter_mut().filter_map(Value::as_object_mut) {
            if !scene.contains_key("nodes") {
                scene.insert("nodes".into(), Value::Array(Vec::new()));
                changed = true;
            }
        }
    }
    changed |= default_spot_cones(value, path, warnings);
    let Some(meshes) = value.get_mut("meshes").and_then(Value::as_array_mut) else {
        return changed;
    };
    for (m, mesh) in meshes.iter_mut().enumerate() {
        let Some(prims) = mesh.get_mut("primitives").and_then(Value::as_array_mut) else {
            continue;
        };
        for (p, prim) in prims.iter_mut().enumerate() {
            let Some(attrs) = prim.get_mut("attributes").and_then(Value::as_object_mut) else {
                continue;
            };
            let custom: Vec<String> = attrs
                .keys()
                .filter(|k| k.starts_with('_'))
                .cloned()
                .collect();
            if custom.is_empty() {
                continue;
            }
            for k in &custom {
                attrs.remove(k);
            }
            changed = true;
            warnings.push(format!(
                "{}: meshes[{m}].primitives[{p}].attributes: application-specific {} {} ignored",
                path.display(),
                if custom.len() == 1 {
                    "attribute"
                } else {
                    "attributes"
                },
                custom.join(", ")
            ));
        }
    }
    changed
}

/// Gives spot lights without a `spot` object an empty one, so the crate reads the
/// extension's default cone (inner 0, outer pi/4) instead of refusing the file; true if any.
fn default_spot_cones(value: &mut Value, path: &Path, warnings: &mut Vec<String>) -> bool {
    let Some(lights) = value
        .pointer_mut("/extensions/KHR_lights_punctual/lights")
        .and_then(Value::as_array_mut)
    else {
        return false;
    };
    let mut changed = false;
    for (i, light) in lights.iter_mut().enumerate() {
        let Some(light) = light.as_object_mut() else {
            continue;
        };
        if light.get("type").and_then(Value::as_str) == Some("spot") && !light.contains_key("spot")
        {
            light.insert("spot".into(), Value::Object(Default::default()));
            changed = true;
            warnings.push(format!(
                "{}: extensions.KHR_lights_punctual.lights[{i}]: a spot light without `spot`; \
                 the default cone (inner 0, outer pi/4) is used",
                path.display()
            ));
        }
    }
    changed
}

/// The validated document: the crate's validation, less the findings the module docs
/// downgrade (each becomes a warning).
pub(super) fn validate(
    root: Root,
    path: &Path,
    warnings: &mut Vec<String>,
) -> Result<Document, SceneError> {
    let mut errors = Vec::new();
    root.validate(&root, gltf::json::Path::new, &mut |at, finding| {
        errors.push((at().as_str().to_string(), finding))
    });
    let mut refused = Vec::new();
    let mut no_bounds: Vec<&str> = Vec::new();
    let position = r#"attributes["POSITION"]"#;
    for (at, finding) in &errors {
        let accessor = at.strip_suffix(".min").or_else(|| at.strip_suffix(".max"));
        match accessor {
            Some(a) if *finding == Finding::Missing && a.ends_with(position) => {
                // `min` and `max` are usually both absent: one warning per primitive.
                if !no_bounds.contains(&a) {
                    no_bounds.push(a);
                    warnings.push(format!(
                        "{}: {a}: the POSITION accessor has no min/max; bounds computed from \
                         the vertices",
                        path.display()
                    ));
                }
            }
            // primitives.rs reports a primitive without POSITION when it is met (not drawn).
            _ if *finding == Finding::Missing && at.ends_with(position) => {}
            // An accessor with neither a buffer view nor sparse values is all zeros by the
            // specification; `accessor::read` makes them (and bounds their number).
            _ if *finding == Finding::Missing
                && at.starts_with("accessors[")
                && at.ends_with("].bufferView") => {}
            _ => refused.push(format!("{at}: {finding}")),
        }
    }
    if refused.is_empty() {
        Ok(Document::from_json_without_validation(root))
    } else {
        Err(SceneError::Gltf {
            path: path.to_path_buf(),
            message: refused.join("; "),
        })
    }
}
