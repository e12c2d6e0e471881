//! The header attributes that say what a render was made from, and those that mark a farm
//! tile ([`crate::farm`]).
//!
//! Every render records its scene (a hash of the files read), seed and settings, so that
//! `lumis merge` can refuse tiles from different renders and a compositor can tell two renders
//! apart. A tile (`--tile I/N`) adds the `lumis/tile*` attributes, which the merge removes:
//!
//! | attribute             | type   | content                                              |
//! |-----------------------|--------|------------------------------------------------------|
//! | `lumis/sceneHash`     | string | SHA-256 of the scene's files and load options (hex)  |
//! | `lumis/seed`          | string | the sample seed, decimal (EXR has no 64-bit integer) |
//! | `lumis/settings`      | string | JSON: the pixel flags as given and every render setting |
//! | `lumis/replay`        | string | JSON: the scene path as given, each input's SHA-256   |
//! | `lumis/tile`          | string | `I/N`                                                |
//! | `lumis/tileExposure`  | string | the exposure the merge applies: `auto` or EV         |
//! | `lumis/tileRgba`      | string | how the merge stores RGBA: `half` or `float`         |
//! | `lumis/tileBeauty`    | string | the names of the R, G, B, A channels, comma-separated |
//! | `lumis/tileDisplay`   | string | the PNG display transform of the render: `srgb` or `clamp` |
//!
//! Both directions live here: [`attributes`] writes them, [`read_identity`] and [`read_tile`]
//! read them back.
//!
//! A tile's RGBA is the film's linear float before exposure: automatic exposure is a function
//! of the whole image, so only the merge can compute it, and applying exposure and the half
//! conversion there, with the same functions as a single render, keeps the merge bit-identical.

use ::exr::meta::header::Header;
use ::exr::prelude::{AttributeValue, SmallVec, Text};

use super::header::text;
use super::layout::ChannelLayout;
use lumis_core::film::DisplayTransform;
use lumis_core::film::TileSpec;
use lumis_core::scene::limits::MAX_EXPOSURE;

/// String attribute: SHA-256 (hex) of the scene's input files and load options.
pub const ATTR_SCENE_HASH: &str = "lumis/sceneHash";
/// String attribute: the seed of the sample streams, in decimal.
pub const ATTR_SEED: &str = "lumis/seed";
/// String attribute: the settings that change the pixels, a JSON object (`flags`: the
/// command's pixel flags as given; `render`: every render setting, by TOML key).
pub const ATTR_SETTINGS: &str = "lumis/settings";
/// String attribute: what `lumis render --from` needs besides the settings, a JSON object
/// (`scene`: the path as given, `null` for the built-in scene; `inputs`: path to SHA-256 of
/// every file read). Not compared by the merge (paths may differ from node to node).
pub const ATTR_REPLAY: &str = "lumis/replay";
/// String attribute of a tile: `I/N`.
pub const ATTR_TILE: &str = "lumis/tile";
/// String attribute of a tile: the exposure for the merge to apply, `auto` or stops.
pub const ATTR_TILE_EXPOSURE: &str = "lumis/tileExposure";
/// String attribute of a tile: `half` or `float`, the merged file's RGBA type.
pub const ATTR_TILE_RGBA: &str = "lumis/tileRgba";
/// String attribute of a tile: the R, G, B, A channel names (after the layout's renaming).
pub const ATTR_TILE_BEAUTY: &str = "lumis/tileBeauty";
/// String attribute of a tile: the display transform a PNG of the merge uses by default.
pub const ATTR_TILE_DISPLAY: &str = "lumis/tileDisplay";
/// What every tile-only attribute's name starts with; the merge drops them all.
pub const TILE_ATTR_PREFIX: &str = "lumis/tile";

/// What a render was made from: two renders with the same identity (and the same lumis) have
/// the same pixels.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RenderIdentity {
    /// SHA-256 (hex) of the input files and load options (see `crate::farm::scene_hash`).
    pub scene_hash: String,
    /// The seed of the sample streams.
    pub seed: u64,
    /// The settings that change the pixels (JSON, see [`ATTR_SETTINGS`]).
    pub settings: String,
    /// What a replay needs besides (JSON, see [`ATTR_REPLAY`]); `None` where there is none.
    pub replay: Option<String>,
}

/// What makes an EXR a farm tile rather than a finished image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TileHeader {
    /// Which tile of how many.
    pub spec: TileSpec,
    /// The exposure in stops the merge applies; `None`: automatic, over the whole image.
    pub exposure: Option<f32>,
    /// The render's PNG display transform, for a PNG preview of the merge.
    pub display: DisplayTransform,
}

/// The `exposure` value of [`ATTR_TILE_EXPOSURE`] for automatic exposure.
pub const TILE_EXPOSURE_AUTO: &str = "auto";

/// The attributes of `identity` and, for a tile, of `tile` (`float_rgba`: the merged RGBA
/// type; `layout`: the channel names).
pub(super) fn attributes(
    identity: Option<&RenderIdentity>,
    tile: Option<&TileHeader>,
    float_rgba: bool,
    layout: ChannelLayout,
) -> Vec<(Text, AttributeValue)> {
    // UTF-8 bytes unchanged, as the Cryptomatte names are written.
    let text = |s: &str| {
        AttributeValue::Text(Text::from_bytes_unchecked(SmallVec::from_vec(
            s.as_bytes().to_vec(),
        )))
    };
    let mut out = Vec::new();
    if let Some(id) = identity {
        out.push((ATTR_SCENE_HASH, text(&id.scene_hash)));
        out.push((ATTR_SEED, text(&id.seed.to_string())));
        out.push((ATTR_SETTINGS, text(&id.settings)));
        if let Some(replay) = &id.replay {
            out.push((ATTR_REPLAY, text(replay)));
        }
    }
    if let Some(tile) = tile {
        // Rust prints the shortest decimal that parses back to the same f32.
        let exposure = tile
            .exposure
            .map_or(TILE_EXPOSURE_AUTO.to_string(), |ev| ev.to_string());
        let beauty = layout.beauty();
        out.push((ATTR_TILE, text(&tile.spec.to_string())));
        out.push((ATTR_TILE_EXPOSURE, text(&exposure)));
        out.push((
            ATTR_TILE_RGBA,
            text(if float_rgba { "float" } else { "half" }),
        ));
        out.push((ATTR_TILE_BEAUTY, text(&beauty.join(","))));
        out.push((ATTR_TILE_DISPLAY, text(tile.display.name())));
    }
    out.into_iter()
        .map(|(name, value)| (Text::from(name), value))
        .collect()
}

/// The identity `header` records: `None` when it has none (a file of another program).
pub(super) fn read_identity(header: &Header) -> Result<Option<RenderIdentity>, String> {
    let (hash, seed, settings) = (
        text(header, ATTR_SCENE_HASH),
        text(header, ATTR_SEED),
        text(header, ATTR_SETTINGS),
    );
    match (hash, seed, settings) {
        (None, None, None) => Ok(None),
        (Some(scene_hash), Some(seed), Some(settings)) => Ok(Some(RenderIdentity {
            scene_hash,
            seed: seed
                .parse()
                .map_err(|_| format!("{ATTR_SEED} = {seed:?}: expected a decimal seed"))?,
            settings,
            replay: text(header, ATTR_REPLAY),
        })),
        _ => Err(format!(
            "{ATTR_SCENE_HASH}, {ATTR_SEED} and {ATTR_SETTINGS}: expected all three or none"
        )),
    }
}

/// What a tile's attributes say besides its [`TileHeader`].
pub(super) struct TileAttributes {
    /// The tile.
    pub tile: TileHeader,
    /// The names of its R, G, B, A channels.
    pub beauty: Vec<String>,
    /// The merged file's RGBA is float (`lumis/tileRgba` = `float`), not half.
    pub float_rgba: bool,
}

/// The tile attributes of `header`; `None` for a file that is no tile (no `lumis/tile`).
pub(super) fn read_tile(header: &Header) -> Result<Option<TileAttributes>, String> {
    let Some(spec) = text(header, ATTR_TILE) else {
        return Ok(None);
    };
    let spec = spec
        .parse::<TileSpec>()
        .map_err(|e| format!("{ATTR_TILE} = {spec:?}: {e}"))?;
    let beauty = text(header, ATTR_TILE_BEAUTY).unwrap_or_default();
    let beauty: Vec<String> = beauty.split(',').map(str::to_string).collect();
    if beauty.len() != 4 {
        return Err(format!(
            "{ATTR_TILE_BEAUTY} = {:?}: expected the names of its four R, G, B, A channels",
            beauty.join(",")
        ));
    }
    let exposure = match text(header, ATTR_TILE_EXPOSURE).as_deref() {
        Some(TILE_EXPOSURE_AUTO) => None,
        Some(ev) => match ev.parse::<f32>() {
            Ok(stops) if stops.abs() <= MAX_EXPOSURE => Some(stops),
            _ => {
                return Err(format!(
                    "{ATTR_TILE_EXPOSURE} = {ev:?}: expected auto or stops within +-{MAX_EXPOSURE}"
                ));
            }
        },
        None => return Err(format!("no {ATTR_TILE_EXPOSURE} attribute")),
    };
    let display = text(header, ATTR_TILE_DISPLAY);
    let display = DisplayTransform::ALL
        .into_iter()
        .find(|d| Some(d.name()) == display.as_deref())
        .ok_or_else(|| {
            format!("{ATTR_TILE_DISPLAY} = {display:?}: expected \"srgb\" or \"clamp\"")
        })?;
    let float_rgba = match text(header, ATTR_TILE_RGBA).as_deref() {
        Some("half") => false,
        Some("float") => true,
        other => {
            return Err(format!(
                "{ATTR_TILE_RGBA} = {other:?}: expected \"half\" or \"float\""
            ));
        }
    };
    Ok(Some(TileAttributes {
        tile: TileHeader {
            spec,
            exposure,
            display,
        },
        beauty,
        float_rgba,
    }))
}
