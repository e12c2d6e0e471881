//! Do the tiles belong together? Compared on the headers as `output::exr` reads them back,
//! before any pixel is decoded: the same render (display window, scene hash, seed, settings
//! and every other header attribute but the tile's own, the timing and the Cryptomatte
//! manifests, which are merged), every tile of the split exactly once, each holding the pixels
//! the split gives it, none of them stopped early.

use std::collections::BTreeMap;

use super::tile::TileFile;
use crate::farm::FarmError;
use crate::output::{
    ATTR_FRAME, ATTR_RENDER_SECONDS, ATTR_RENDERER, ATTR_REPLAY, ATTR_SCENE_HASH, ATTR_SEED,
    ATTR_SETTINGS, ATTR_TILE,
};
use crate::output::{ExrHeader, HeaderValue};

/// Whether attribute `name` may differ between the tiles of one render: the index, the
/// timing, the manifests (merged). The other tile attributes say how to finish the image and
/// must agree.
pub fn varies_per_tile(name: &str) -> bool {
    // The replay record holds paths, which may differ from node to node; the merged file
    // keeps the first tile's.
    name == ATTR_TILE || name == ATTR_RENDER_SECONDS || name == ATTR_REPLAY || is_manifest(name)
}

/// Whether a `lumis/settings` value is the JSON record (not an older lumis's text lines).
pub fn is_settings_record(value: &str) -> bool {
    serde_json::from_str::<serde_json::Value>(value).is_ok_and(|v| v.is_object())
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
        if tile.file.header().meta.partial {
            return Err(FarmError::Partial {
                path: tile.path().to_path_buf(),
                spec: tile.spec(),
            });
        }
    }
    check_split(tiles)
}

/// Every index once, each tile holding the split's window.
fn check_split(tiles: &[TileFile]) -> Result<(), FarmError> {
    let count = tiles[0].spec().count;
    let mut seen: BTreeMap<u32, &TileFile> = BTreeMap::new();
    for tile in tiles {
        let spec = tile.spec();
        if let Some(earlier) = seen.insert(spec.index, tile) {
            return Err(FarmError::Duplicate {
                spec,
                first: earlier.path().to_path_buf(),
                second: tile.path().to_path_buf(),
            });
        }
        let (w, h) = tile.full_size();
        let want = spec.window(w, h).map_err(|message| FarmError::Format {
            path: tile.path().to_path_buf(),
            message,
        })?;
        let got = tile.window();
        if got != want {
            return Err(FarmError::Format {
                path: tile.path().to_path_buf(),
                message: format!(
                    "tile {} holds pixels x {}..{}, y {}..{}, but tile {} of a {w}x{h} image \
                     is x {}..{}, y {}..{} (a tile must be written by `lumis render --tile`)",
                    spec, got.x0, got.x1, got.y0, got.y1, spec, want.x0, want.x1, want.y0, want.y1
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
        path: tile.path().to_path_buf(),
        first: first.path().to_path_buf(),
        what,
        detail,
    };
    let (a, b) = (first.file.header(), tile.file.header());
    if let Some(settings) = b.attributes.get(ATTR_SETTINGS)
        && !is_settings_record(&settings.to_string())
    {
        return Err(FarmError::Format {
            path: tile.path().to_path_buf(),
            message: format!(
                "{ATTR_SETTINGS} is the text record of an older lumis, not the JSON one this \
                 lumis writes and compares: render the tile again with this lumis"
            ),
        });
    }
    if tile.spec().count != first.spec().count {
        return Err(mismatch(
            "the tile count".into(),
            format!("tile {} against {}", tile.spec(), first.spec()),
        ));
    }
    if a.full_size != b.full_size {
        return Err(mismatch(
            "the display window (the image size)".into(),
            format!(
                "{}x{} against {}x{}",
                b.full_size.0, b.full_size.1, a.full_size.0, a.full_size.1
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
        let (va, vb) = (a.attributes.get(name), b.attributes.get(name));
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
    if a.channels != b.channels {
        return Err(mismatch(
            "the channel list".into(),
            format!(
                "{} against {}",
                b.channels.join(", "),
                a.channels.join(", ")
            ),
        ));
    }
    if a.standard != b.standard {
        return Err(mismatch(
            "the standard header (camera matrices, chromaticities, compression)".into(),
            "one of its attributes".into(),
        ));
    }
    Ok(())
}

/// The first custom attribute, in name order, that one header has differently or only.
fn differing_attribute(a: &ExrHeader, b: &ExrHeader) -> Option<String> {
    let (ca, cb) = (custom(a), custom(b));
    ca.keys()
        .chain(cb.keys())
        .find(|k| ca.get(*k) != cb.get(*k))
        .map(|k| k.to_string())
}

/// The custom attributes that must agree, by name.
fn custom(h: &ExrHeader) -> BTreeMap<&str, &HeaderValue> {
    h.attributes
        .iter()
        .map(|(k, v)| (k.as_str(), v))
        .filter(|(k, _)| !varies_per_tile(k))
        .collect()
}

/// The two values of a differing identity attribute; of two settings records, the keys that
/// differ.
fn settings_detail(tile: Option<&HeaderValue>, first: Option<&HeaderValue>) -> String {
    let show = |v: Option<&HeaderValue>| v.map_or("absent".to_string(), |v| v.to_string());
    let (t, f) = (show(tile), show(first));
    let parse = |s: &str| serde_json::from_str::<serde_json::Value>(s).ok();
    if let (Some(jt), Some(jf)) = (parse(&t), parse(&f)) {
        let mut keys = Vec::new();
        differing_keys("", &jt, &jf, &mut keys);
        if !keys.is_empty() {
            return keys.join("; ");
        }
    }
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
        // A line one side has and the other lacks (e.g. `adaptive: Some(0.05)`, which a render
        // without adaptive supersampling leaves out).
        let side = |lines: Vec<&str>| match lines.is_empty() {
            true => "no such line".to_string(),
            false => lines.join("; "),
        };
        return format!("{} against {}", side(only), side(theirs));
    }
    format!("{t} against {f}")
}

/// The keys (`flags.--spp`, `render.width`) at which `a` and `b` differ, each with both values.
fn differing_keys(at: &str, a: &serde_json::Value, b: &serde_json::Value, out: &mut Vec<String>) {
    use serde_json::Value;
    match (a, b) {
        (Value::Object(ma), Value::Object(mb)) => {
            let keys: std::collections::BTreeSet<&String> = ma.keys().chain(mb.keys()).collect();
            for k in keys {
                let path = if at.is_empty() {
                    k.clone()
                } else {
                    format!("{at}.{k}")
                };
                match (ma.get(k), mb.get(k)) {
                    (Some(x), Some(y)) => differing_keys(&path, x, y, out),
                    (x, y) => out.push(format!(
                        "{path}: {} against {}",
                        x.map_or("absent".to_string(), Value::to_string),
                        y.map_or("absent".to_string(), Value::to_string)
                    )),
                }
            }
        }
        _ if a != b => out.push(format!("{at}: {a} against {b}")),
        _ => {}
    }
}
