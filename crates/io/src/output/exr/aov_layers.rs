//! The AOV layers written only on request (`--aov albedo,position,uv`), all FLOAT, from the
//! centre ray of each pixel like the depth, normal and id layers:
//!
//! | channel             | content                                                        |
//! |---------------------|----------------------------------------------------------------|
//! | `albedo.R/G/B`      | diffuse albedo `kd` at the hit (textures evaluated); 0 at misses |
//! | `P.X/Y/Z`           | world-space hit point; 0 at misses                             |
//! | `uv.U/V`            | texture coordinates at the hit; 0 at misses                    |
//! | `uv.A` (Blender layout only) | 1 where the centre ray hit a surface, 0 at misses     |
//! | `id.instance`       | index of the instance hit (the scene's list); -1 at misses and on surfaces of no instance |
//! | `samples`           | pixel samples the pixel took: `spp x spp`, fewer where `--adaptive` kept its base pass |
//!
//! `id.instance` is no request: a render writes it whenever its scene has instances (beside
//! `id.prim`, which is then the prototype's primitive, and `id.object`, the instance's own
//! object), and never otherwise, so that the files of scenes without instances keep the
//! channels, and the bytes, they had before instancing.

use super::layout::ChannelLayout;
use lumis_core::film::{Film, PixelAov};

/// Which of the optional AOV layers to write.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AovLayers {
    /// `albedo.R/G/B`.
    pub albedo: bool,
    /// `P.X/Y/Z` (world position).
    pub position: bool,
    /// `uv.U/V`.
    pub uv: bool,
    /// `samples`: the pixel samples each pixel took (not from the centre ray).
    pub samples: bool,
    /// `id.instance`: set from the scene (it has instances), not asked for.
    pub instance: bool,
}

/// One optional channel: its layer, lumis name, value from a pixel's AOV and, unless it is
/// derived from other channels, where a reader stores it. The writer and the reader both go
/// through this table, so the two cannot disagree on a name.
struct AovChannel {
    layer: fn(AovLayers) -> bool,
    name: &'static str,
    get: fn(&PixelAov) -> f32,
    set: Option<fn(&mut PixelAov, f32)>,
}

const CHANNELS: [AovChannel; 11] = [
    AovChannel {
        layer: |l| l.albedo,
        name: "albedo.R",
        get: |a| a.albedo.x,
        set: Some(|a, v| a.albedo.x = v),
    },
    AovChannel {
        layer: |l| l.albedo,
        name: "albedo.G",
        get: |a| a.albedo.y,
        set: Some(|a, v| a.albedo.y = v),
    },
    AovChannel {
        layer: |l| l.albedo,
        name: "albedo.B",
        get: |a| a.albedo.z,
        set: Some(|a, v| a.albedo.z = v),
    },
    AovChannel {
        layer: |l| l.position,
        name: "P.X",
        get: |a| a.position.x,
        set: Some(|a, v| a.position.x = v),
    },
    AovChannel {
        layer: |l| l.position,
        name: "P.Y",
        get: |a| a.position.y,
        set: Some(|a, v| a.position.y = v),
    },
    AovChannel {
        layer: |l| l.position,
        name: "P.Z",
        get: |a| a.position.z,
        set: Some(|a, v| a.position.z = v),
    },
    AovChannel {
        layer: |l| l.uv,
        name: "uv.U",
        get: |a| a.uv.x,
        set: Some(|a, v| a.uv.x = v),
    },
    AovChannel {
        layer: |l| l.uv,
        name: "uv.V",
        get: |a| a.uv.y,
        set: Some(|a, v| a.uv.y = v),
    },
    // Blender's third UV channel: derived from the object id, so nothing to store.
    AovChannel {
        layer: |l| l.uv,
        name: "uv.A",
        get: |a| if a.object_id >= 0 { 1.0 } else { 0.0 },
        set: None,
    },
    // An index like `id.object`, stored as a float holding an integer; the reader checks it is
    // one (every `id.` channel).
    AovChannel {
        layer: |l| l.instance,
        name: "id.instance",
        get: |a| a.instance_id as f32,
        set: Some(|a, v| a.instance_id = v as i32),
    },
    // A count, exact in a float up to 2^24 (spp 64 makes 4096).
    AovChannel {
        layer: |l| l.samples,
        name: "samples",
        get: |a| a.samples as f32,
        set: Some(|a, v| a.samples = v as u32),
    },
];

/// The table's channels of `layers` in `layout` (`uv.A` only where the layout has it).
fn table(layers: AovLayers, layout: ChannelLayout) -> impl Iterator<Item = &'static AovChannel> {
    CHANNELS
        .iter()
        .filter(move |c| (c.layer)(layers) && (c.name != "uv.A" || layout.uv_has_alpha()))
}

/// The requested layers' channels of `film`, as (lumis name, values row-major), with the
/// extra channels `layout` has.
pub(super) fn channels(
    film: &Film,
    layers: AovLayers,
    layout: ChannelLayout,
) -> Vec<(&'static str, Vec<f32>)> {
    let aov = film.aov();
    table(layers, layout)
        .map(|c| (c.name, aov.iter().map(c.get).collect()))
        .collect()
}

/// Which layers a file holds, by the first channel of each (`has` tells whether a channel of
/// that name, in `layout`, is in the file).
pub(super) fn present(layout: ChannelLayout, has: impl Fn(&str) -> bool) -> AovLayers {
    let first = |name: &str| has(&layout.channel(name));
    AovLayers {
        albedo: first("albedo.R"),
        position: first("P.X"),
        uv: first("uv.U"),
        samples: first("samples"),
        instance: first("id.instance"),
    }
}

/// The lumis names of the channels `layers` has in `layout`.
pub(super) fn names(layers: AovLayers, layout: ChannelLayout) -> Vec<&'static str> {
    table(layers, layout).map(|c| c.name).collect()
}

/// Stores `value` of the channel with lumis name `name` in `aov` (nothing for a derived one).
pub(super) fn store(aov: &mut PixelAov, name: &str, value: f32) {
    if let Some(set) = CHANNELS.iter().find(|c| c.name == name).and_then(|c| c.set) {
        set(aov, value);
    }
}
