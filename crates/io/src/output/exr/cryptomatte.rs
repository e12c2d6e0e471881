//! The Cryptomatte layers of the EXR, as the Cryptomatte specification 1.1.0 lays them out:
//! for each type (`CryptoObject`, `CryptoMaterial`) FLOAT channels `{type}00.R/G/B/A`,
//! `{type}01.R/G/B/A`, ... holding (id, coverage) of ranks 0 and 1, 2 and 3, ..., and the
//! header attributes `cryptomatte/<key>/name`, `/hash` (`MurmurHash3_32`), `/conversion`
//! (`uint32_to_float32`) and `/manifest` (JSON, name to the id's float bits in hex), `<key>`
//! being the first 7 hex digits of the MurmurHash3 of the type name.
//!
//! Ids are FLOAT, never half: they are hash bits, and rounding them would name another
//! object. With an odd number of levels the last layer's B and A are id 0, coverage 0.

use std::collections::BTreeMap;

use ::exr::meta::header::Header;
use ::exr::prelude::{AttributeValue, SmallVec, Text};

use super::header::text;
use super::layout::ChannelLayout;
use lumis_core::cryptomatte::{CryptoLayer, MAX_LEVELS, Rank, metadata_key};

/// The channels of `layer` in the lumis layout (`CryptoObject00.R`): (name, values
/// row-major). The EXR writer renames every channel by the layout, these too, which makes them
/// `ViewLayer.CryptoObject00.R` for Blender: the type name [`attributes`] records plus the
/// rank suffix, as readers match them.
pub(super) fn channels(layer: &CryptoLayer) -> Vec<(String, Vec<f32>)> {
    let levels = layer.levels();
    let pixels = layer.ranks().len() / levels;
    channel_names(layer.name(), levels)
        .into_iter()
        .enumerate()
        .map(|(c, name)| {
            // Channel c holds rank c / 2: its id (even c) or its coverage (odd c).
            let rank = c / 2;
            let values = (0..pixels)
                .map(|i| match layer.pixel(i).get(rank) {
                    Some(r) if c % 2 == 0 => f32::from_bits(r.id),
                    Some(r) => r.coverage,
                    None => 0.0,
                })
                .collect();
            (name, values)
        })
        .collect()
}

/// The lumis names of the channels of a layer of type `type_name` with `levels` ranks, in rank
/// order: `{type}00.R` (rank 0's id), `{type}00.G` (its coverage), `{type}00.B`, ...
fn channel_names(type_name: &str, levels: usize) -> Vec<String> {
    (0..levels.div_ceil(2))
        .flat_map(|part| {
            ["R", "G", "B", "A"].map(|channel| format!("{type_name}{part:02}.{channel}"))
        })
        .collect()
}

/// The header attributes describing `layer` (named by `layout`).
pub(super) fn attributes(
    layer: &CryptoLayer,
    layout: ChannelLayout,
) -> Vec<(Text, AttributeValue)> {
    let type_name = layout.crypto_type(layer.name());
    let prefix = format!("cryptomatte/{}", metadata_key(&type_name));
    let text = |s: String| {
        // Names are UTF-8 and hashed as such; EXR strings are bytes, written unchanged.
        AttributeValue::Text(Text::from_bytes_unchecked(SmallVec::from_vec(
            s.into_bytes(),
        )))
    };
    [
        ("name", type_name.clone()),
        ("hash", "MurmurHash3_32".to_string()),
        ("conversion", "uint32_to_float32".to_string()),
        ("manifest", layer.manifest_json()),
    ]
    .into_iter()
    .map(|(key, value)| (Text::from(format!("{prefix}/{key}").as_str()), text(value)))
    .collect()
}

/// A Cryptomatte layer as a header describes it, its pixels not decoded yet.
#[derive(Clone, Debug, PartialEq)]
pub struct CryptoHeader {
    /// The type name in the lumis layout (`CryptoObject`).
    pub name: String,
    /// Ranks per pixel: two per `{type}NN` RGBA channel group (an odd count written by a
    /// render reads back one higher, its last rank empty, which writes the same channels).
    pub levels: u32,
    /// Name to id bits, as `/manifest` lists them.
    pub manifest: BTreeMap<String, u32>,
}

impl CryptoHeader {
    /// The file's names (in `layout`) of this layer's channels, in rank order.
    pub(super) fn channels(&self, layout: ChannelLayout) -> Vec<String> {
        channel_names(&self.name, self.levels as usize)
            .iter()
            .map(|n| layout.channel(n))
            .collect()
    }

    /// The layer of `pixels` pixels whose channels (in [`Self::channels`] order) are `values`.
    pub(super) fn layer(&self, values: &[&[f32]], pixels: usize) -> Result<CryptoLayer, String> {
        let levels = self.levels as usize;
        let mut ranks = Vec::new();
        ranks
            .try_reserve_exact(pixels * levels)
            .map_err(|_| format!("not enough memory for the {} layer", self.name))?;
        ranks.extend((0..pixels).flat_map(|i| {
            (0..levels).map(move |rank| Rank {
                id: values[2 * rank][i].to_bits(),
                coverage: values[2 * rank + 1][i],
            })
        }));
        CryptoLayer::from_ranks(&self.name, self.manifest.clone(), self.levels, ranks)
    }
}

/// The Cryptomatte layers `header` describes (the `cryptomatte/<key>/name` attributes), in key
/// order; `has` tells whether the file has a channel of that name.
pub(super) fn read_headers(
    header: &Header,
    layout: ChannelLayout,
    has: impl Fn(&str) -> bool,
) -> Result<Vec<CryptoHeader>, String> {
    let mut keys: Vec<String> = header
        .own_attributes
        .other
        .keys()
        .filter_map(|k| {
            let k = k.to_string();
            let key = k.strip_prefix("cryptomatte/")?.strip_suffix("/name")?;
            Some(key.to_string())
        })
        .collect();
    keys.sort();
    let mut out = Vec::new();
    for key in keys {
        let attr = |what: &str| text(header, &format!("cryptomatte/{key}/{what}"));
        let recorded = attr("name").unwrap_or_default();
        let name = layout
            .crypto_name(&recorded)
            .filter(|_| metadata_key(&recorded) == key)
            .ok_or_else(|| {
                format!(
                    "cryptomatte/{key}/name = {recorded:?}: not a layer name of this file's \
                     layout and key"
                )
            })?
            .to_string();
        for (what, want) in [
            ("hash", "MurmurHash3_32"),
            ("conversion", "uint32_to_float32"),
        ] {
            if attr(what).as_deref() != Some(want) {
                return Err(format!("cryptomatte/{key}/{what}: expected {want:?}"));
            }
        }
        let manifest = parse_manifest(&attr("manifest").unwrap_or_default())
            .map_err(|e| format!("cryptomatte/{key}/manifest: {e}"))?;
        let parts = (0..)
            .take_while(|p| has(&layout.channel(&format!("{name}{p:02}.R"))))
            .count() as u32;
        if parts == 0 || 2 * parts > MAX_LEVELS {
            return Err(format!(
                "Cryptomatte layer {recorded}: {parts} channel groups {recorded}NN, expected 1..={}",
                MAX_LEVELS / 2
            ));
        }
        out.push(CryptoHeader {
            name,
            levels: 2 * parts,
            manifest,
        });
    }
    Ok(out)
}

/// A manifest as [`CryptoLayer::manifest_json`] writes it: names to 8 hex digits of the id.
fn parse_manifest(json: &str) -> Result<BTreeMap<String, u32>, String> {
    let parsed: serde_json::Map<String, serde_json::Value> = serde_json::from_str(json)
        .map_err(|e| format!("not a JSON object of names to ids: {e}"))?;
    parsed
        .into_iter()
        .map(|(name, id)| {
            let bits = id
                .as_str()
                .and_then(|hex| u32::from_str_radix(hex, 16).ok())
                .ok_or_else(|| format!("{name:?} has id {id}, expected 8 hex digits"))?;
            Ok((name, bits))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The written name of every channel starts with the type name of the metadata, in both
    /// layouts (a reader finds the ranks as `{name}00.R`).
    #[test]
    fn channels_renamed_by_the_layout_start_with_the_recorded_type_name() {
        let layer = CryptoLayer::new("CryptoObject", &["a", "b"], 3, 2);
        for layout in [ChannelLayout::Lumis, ChannelLayout::Blender] {
            let names: Vec<String> = channels(&layer)
                .into_iter()
                .map(|(n, _)| layout.channel(&n))
                .collect();
            let recorded = attributes(&layer, layout)
                .into_iter()
                .find(|(k, _)| k.to_string().ends_with("/name"))
                .map(|(_, v)| match v {
                    AttributeValue::Text(t) => t.to_string(),
                    other => panic!("{other:?}"),
                })
                .unwrap();
            let want: Vec<String> = [
                "00.R", "00.G", "00.B", "00.A", "01.R", "01.G", "01.B", "01.A",
            ]
            .iter()
            .map(|s| format!("{recorded}{s}"))
            .collect();
            assert_eq!(names, want, "{layout:?}");
        }
    }
}
