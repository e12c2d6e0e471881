//! The colour of the assembled image finished as a single render finishes its film (exposure,
//! then half or float), and the Cryptomatte manifests merged.

use std::collections::BTreeSet;
use std::path::Path;

use ::exr::prelude::{AnyChannel, AttributeValue, FlatSamples, SmallVec, Text};

use super::check::is_manifest;
use super::read::{TileFile, text};
use crate::farm::FarmError;
use crate::output::{
    ATTR_TILE_BEAUTY, ATTR_TILE_DISPLAY, ATTR_TILE_EXPOSURE, ATTR_TILE_RGBA, TILE_EXPOSURE_AUTO,
    half_rgba,
};
use lumis_core::film::{DisplayTransform, auto_exposure_of, expose_rgba};
use lumis_core::math::Vec4;
use lumis_core::scene::limits::MAX_EXPOSURE;

/// How the merge finished the colour.
pub struct Finished {
    /// The exposure applied, in stops.
    pub stops: f32,
    /// Computed over the whole image.
    pub automatic: bool,
    /// The exposed RGBA in float (before the half conversion).
    pub rgba: Vec<Vec4>,
    /// The render's PNG display transform.
    pub display: DisplayTransform,
}

/// What the exposure attribute said.
struct Exposure {
    stops: f32,
    automatic: bool,
}

/// An error naming the first tile, whose header describes the finishing.
fn format(first: &TileFile, message: String) -> FarmError {
    FarmError::Format {
        path: first.path.clone(),
        message,
    }
}

/// Exposes the R, G, B, A channels (the tiles' unexposed floats) and stores them as the
/// single render would: half, clamped to its range, or float.
pub fn finish_rgba(
    first: &TileFile,
    channels: &mut [AnyChannel<FlatSamples>],
) -> Result<Finished, FarmError> {
    let header = &first.header;
    let beauty = text(header, ATTR_TILE_BEAUTY).unwrap_or_default();
    let names: Vec<&str> = beauty.split(',').collect();
    let index = |name: &str| channels.iter().position(|c| c.name.to_string() == name);
    let indices: Option<Vec<usize>> = if names.len() == 4 {
        names.iter().map(|n| index(n)).collect()
    } else {
        None
    };
    let indices = indices.ok_or_else(|| {
        format(
            first,
            format!("{ATTR_TILE_BEAUTY} = {beauty:?}: expected the names of its four R, G, B, A channels"),
        )
    })?;
    let mut rgba = Vec::new();
    for (component, &i) in indices.iter().enumerate() {
        let FlatSamples::F32(values) = &channels[i].sample_data else {
            return Err(format(
                first,
                format!(
                    "channel {} is not FLOAT; a tile keeps RGBA as float",
                    channels[i].name
                ),
            ));
        };
        if rgba.is_empty() {
            rgba = vec![Vec4::ZERO; values.len()];
        }
        for (p, &v) in rgba.iter_mut().zip(values) {
            p[component] = v;
        }
    }
    if rgba.iter().any(|p| !p.is_finite()) {
        return Err(format(
            first,
            "the tiles' RGBA holds an infinite value".into(),
        ));
    }
    let exposure = match text(header, ATTR_TILE_EXPOSURE).as_deref() {
        Some(TILE_EXPOSURE_AUTO) => Exposure {
            stops: auto_exposure_of(&rgba),
            automatic: true,
        },
        Some(ev) => match ev.parse::<f32>() {
            Ok(stops) if stops.abs() <= MAX_EXPOSURE => Exposure {
                stops,
                automatic: false,
            },
            _ => {
                return Err(format(
                    first,
                    format!(
                        "{ATTR_TILE_EXPOSURE} = {ev:?}: expected auto or stops within +-{MAX_EXPOSURE}"
                    ),
                ));
            }
        },
        None => return Err(format(first, format!("no {ATTR_TILE_EXPOSURE} attribute"))),
    };
    let display = text(header, ATTR_TILE_DISPLAY);
    let display = DisplayTransform::ALL
        .into_iter()
        .find(|d| Some(d.name()) == display.as_deref())
        .ok_or_else(|| {
            format(
                first,
                format!("{ATTR_TILE_DISPLAY} = {display:?}: expected \"srgb\" or \"clamp\""),
            )
        })?;
    expose_rgba(&mut rgba, exposure.stops);
    let half = match text(header, ATTR_TILE_RGBA).as_deref() {
        Some("half") => true,
        Some("float") => false,
        other => {
            return Err(format(
                first,
                format!("{ATTR_TILE_RGBA} = {other:?}: expected \"half\" or \"float\""),
            ));
        }
    };
    for (component, &i) in indices.iter().enumerate() {
        let values = rgba.iter().map(|p| p[component]);
        channels[i].sample_data = if half {
            FlatSamples::F16(values.map(half_rgba).collect())
        } else {
            FlatSamples::F32(values.collect())
        };
    }
    Ok(Finished {
        stops: exposure.stops,
        automatic: exposure.automatic,
        rgba,
        display,
    })
}

/// An error when a tile's channel holds NaN (lumis writes none; a damaged tile might).
pub fn reject_nan(samples: &FlatSamples, name: &Text, path: &Path) -> Result<(), FarmError> {
    let nan = match samples {
        FlatSamples::F16(v) => v.iter().any(|x| x.is_nan()),
        FlatSamples::F32(v) => v.iter().any(|x| x.is_nan()),
        FlatSamples::U32(_) => false,
    };
    if nan {
        return Err(FarmError::Format {
            path: path.to_path_buf(),
            message: format!("channel {name} holds NaN"),
        });
    }
    Ok(())
}

/// Every Cryptomatte manifest attribute of the tiles: kept as it is when every tile has the
/// same (lumis's manifests list the scene's names, so they do), otherwise the union of the
/// names, an error if one name has two ids.
pub fn merged_manifests(tiles: &[TileFile]) -> Result<Vec<(Text, AttributeValue)>, FarmError> {
    let names: BTreeSet<String> = tiles
        .iter()
        .flat_map(|t| t.header.own_attributes.other.keys().map(|k| k.to_string()))
        .filter(|k| is_manifest(k))
        .collect();
    let mut out = Vec::new();
    for name in names {
        let values: Vec<Option<String>> = tiles.iter().map(|t| text(&t.header, &name)).collect();
        let merged = if values.iter().all(|v| v.is_some() && *v == values[0]) {
            values[0].clone().unwrap_or_default()
        } else {
            union(tiles, &name, &values)?
        };
        let value = AttributeValue::Text(Text::from_bytes_unchecked(SmallVec::from_vec(
            merged.into_bytes(),
        )));
        out.push((Text::from(name.as_str()), value));
    }
    Ok(out)
}

/// The union of the JSON manifests `values` (one per tile, absent ones skipped).
fn union(tiles: &[TileFile], name: &str, values: &[Option<String>]) -> Result<String, FarmError> {
    let mut map = serde_json::Map::new();
    for (tile, value) in tiles.iter().zip(values) {
        let Some(value) = value else { continue };
        let bad = |detail: String| FarmError::Format {
            path: tile.path.clone(),
            message: format!("{name}: {detail}"),
        };
        let parsed: serde_json::Map<String, serde_json::Value> = serde_json::from_str(value)
            .map_err(|e| bad(format!("not a JSON object of names to ids: {e}")))?;
        for (key, id) in parsed {
            if let Some(earlier) = map.get(&key)
                && *earlier != id
            {
                return Err(FarmError::Mismatch {
                    path: tile.path.clone(),
                    first: tiles[0].path.clone(),
                    what: format!("the Cryptomatte manifest {name}"),
                    detail: format!("{key:?} has id {id} here and {earlier} elsewhere"),
                });
            }
            map.insert(key, id);
        }
    }
    Ok(serde_json::Value::Object(map).to_string())
}
