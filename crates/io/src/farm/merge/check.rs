//! Do the tiles belong together? The same render (display window, scene hash, seed, settings
//! and every other header attribute but the tile's own, the timing and the Cryptomatte
//! manifests, which are merged), every tile of the split exactly once, each holding the pixels
//! the split gives it, none of them stopped early.

use std::collections::BTreeMap;

use ::exr::meta::header::Header;
use ::exr::prelude::{AttributeValue, LayerAttributes, Text, Vec2};

use super::read::TileFile;
use crate::farm::FarmError;
use crate::output::{
    ATTR_FRAME, ATTR_PARTIAL, ATTR_RENDER_SECONDS, ATTR_RENDERER, ATTR_SCENE_HASH, ATTR_SEED,
    ATTR_SETTINGS, ATTR_TILE, TILE_ATTR_PREFIX,
};

/// Whether attribute `name` may differ between the tiles of one render: the index, the
/// timing, the manifests (merged). The other tile attributes say how to finish the image and
/// must agree.
pub fn varies_per_tile(name: &str) -> bool {
    name == ATTR_TILE || name == ATTR_RENDER_SECONDS || is_manifest(name)
}

/// Whether the merged file leaves out attribute `name` (or writes it anew): the tile's own,
/// the timing (summed), the manifests (merged).
pub fn left_out_of_merge(name: &str) -> bool {
    name.starts_with(TILE_ATTR_PREFIX) || name == ATTR_RENDER_SECONDS || is_manifest(name)
}

/// A Cryptomatte manifest attribute (`cryptomatte/<key>/manifest`).
pub fn is_manifest(name: &str) -> bool {
    name.starts_with("cryptomatte/") && name.ends_with("/manifest")
}

/// Checks that `tiles` are the whole split of one render, the first tile being the reference.
pub fn check_tiles(tiles: &[TileFile]) -> Result<(), FarmError> {
    let first = tiles.first().ok_or(FarmError::NoTiles)?;
    for tile in tiles {
        check_same_render(first, tile)?;
        if tile
            .header
            .own_attributes
            .other
            .contains_key(&Text::from(ATTR_PARTIAL))
        {
            return Err(FarmError::Partial {
                path: tile.path.clone(),
                spec: tile.spec,
            });
        }
    }
    check_split(tiles)
}

/// Every index once, each tile holding the split's window.
fn check_split(tiles: &[TileFile]) -> Result<(), FarmError> {
    let count = tiles[0].spec.count;
    let mut seen: BTreeMap<u32, &TileFile> = BTreeMap::new();
    for tile in tiles {
        if let Some(earlier) = seen.insert(tile.spec.index, tile) {
            return Err(FarmError::Duplicate {
                spec: tile.spec,
                first: earlier.path.clone(),
                second: tile.path.clone(),
            });
        }
        let (w, h) = tile.full_size();
        let want = tile
            .spec
            .window(w, h)
            .map_err(|message| FarmError::Format {
                path: tile.path.clone(),
                message,
            })?;
        let got = tile.window();
        if got != want {
            return Err(FarmError::Format {
                path: tile.path.clone(),
                message: format!(
                    "tile {} holds pixels x {}..{}, y {}..{}, but tile {} of a {w}x{h} image \
                     is x {}..{}, y {}..{} (a tile must be written by `lumis render --tile`)",
                    tile.spec,
                    got.x0,
                    got.x1,
                    got.y0,
                    got.y1,
                    tile.spec,
                    want.x0,
                    want.x1,
                    want.y0,
                    want.y1
                ),
            });
        }
    }
    let missing: Vec<u32> = (0..count).filter(|i| !seen.contains_key(i)).collect();
    if !missing.is_empty() {
        return Err(FarmError::Missing { count, missing });
    }
    Ok(())
}

/// Everything in `tile`'s header that a single render fixes equals `first`'s.
fn check_same_render(first: &TileFile, tile: &TileFile) -> Result<(), FarmError> {
    let mismatch = |what: String, detail: String| FarmError::Mismatch {
        path: tile.path.clone(),
        first: first.path.clone(),
        what,
        detail,
    };
    let (a, b) = (&first.header, &tile.header);
    if tile.spec.count != first.spec.count {
        return Err(mismatch(
            "the tile count".into(),
            format!("tile {} against {}", tile.spec, first.spec),
        ));
    }
    let (da, db) = (
        &a.shared_attributes.display_window,
        &b.shared_attributes.display_window,
    );
    if da != db {
        return Err(mismatch(
            "the display window (the image size)".into(),
            format!(
                "{}x{} against {}x{}",
                db.size.0, db.size.1, da.size.0, da.size.1
            ),
        ));
    }
    for (name, what) in [
        (
            ATTR_SCENE_HASH,
            "the scene (lumis/sceneHash, a hash of its files)",
        ),
        (ATTR_SEED, "the seed (lumis/seed)"),
        (ATTR_SETTINGS, "the settings record (lumis/settings)"),
        (ATTR_RENDERER, "the lumis version (lumis/renderer)"),
        // The frame poses the scene after it is loaded, so the scene hash cannot see it.
        (ATTR_FRAME, "the frame of the animation (lumis/frame)"),
    ] {
        let (va, vb) = (attribute(a, name), attribute(b, name));
        if va != vb {
            return Err(mismatch(what.into(), settings_detail(vb, va)));
        }
    }
    if let Some(name) = differing_attribute(a, b) {
        return Err(mismatch(
            format!("the header attribute {name}"),
            "its value".into(),
        ));
    }
    let names = |h: &Header| -> Vec<String> {
        h.channels
            .list
            .iter()
            .map(|c| format!("{} ({:?})", c.name, c.sample_type))
            .collect()
    };
    if a.channels != b.channels {
        return Err(mismatch(
            "the channel list".into(),
            format!("{} against {}", names(b).join(", "), names(a).join(", ")),
        ));
    }
    if (a.compression, a.line_order) != (b.compression, b.line_order)
        || a.shared_attributes.pixel_aspect != b.shared_attributes.pixel_aspect
        || a.shared_attributes.chromaticities != b.shared_attributes.chromaticities
        || a.shared_attributes.time_code != b.shared_attributes.time_code
        || !a.shared_attributes.other.is_empty()
        || !b.shared_attributes.other.is_empty()
        || standard(&a.own_attributes) != standard(&b.own_attributes)
    {
        return Err(mismatch(
            "the standard header (camera matrices, chromaticities, compression)".into(),
            "one of its attributes".into(),
        ));
    }
    Ok(())
}

/// The first custom attribute, in name order, that one header has differently or only.
fn differing_attribute(a: &Header, b: &Header) -> Option<String> {
    let (ca, cb) = (custom(a), custom(b));
    ca.keys()
        .chain(cb.keys())
        .find(|k| ca.get(*k) != cb.get(*k))
        .cloned()
}

/// The custom attributes that must agree, by name.
fn custom(h: &Header) -> BTreeMap<String, &AttributeValue> {
    h.own_attributes
        .other
        .iter()
        .map(|(k, v)| (k.to_string(), v))
        .filter(|(k, _)| !varies_per_tile(k))
        .collect()
}

/// The layer's standard attributes, without its position and its custom ones.
fn standard(attributes: &LayerAttributes) -> LayerAttributes {
    LayerAttributes {
        layer_position: Vec2(0, 0),
        other: Default::default(),
        ..attributes.clone()
    }
}

fn attribute<'h>(header: &'h Header, name: &str) -> Option<&'h AttributeValue> {
    header.own_attributes.other.get(&Text::from(name))
}

/// The two values of a differing identity attribute, the settings as their differing lines.
fn settings_detail(tile: Option<&AttributeValue>, first: Option<&AttributeValue>) -> String {
    let show = |v: Option<&AttributeValue>| -> String {
        match v {
            Some(AttributeValue::Text(t)) => String::from_utf8_lossy(t.bytes()).into_owned(),
            Some(other) => format!("{other:?}"),
            None => "absent".into(),
        }
    };
    let (t, f) = (show(tile), show(first));
    let lines_t: Vec<&str> = t.lines().collect();
    let lines_f: Vec<&str> = f.lines().collect();
    if lines_t.len() > 1 || lines_f.len() > 1 {
        let only: Vec<&str> = lines_t
            .iter()
            .filter(|l| !lines_f.contains(l))
            .copied()
            .collect();
        let theirs: Vec<&str> = lines_f
            .iter()
            .filter(|l| !lines_t.contains(l))
            .copied()
            .collect();
        return format!("{} against {}", only.join("; "), theirs.join("; "));
    }
    format!("{t} against {f}")
}
