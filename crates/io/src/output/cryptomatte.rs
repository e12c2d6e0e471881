//! The Cryptomatte layers of the EXR, as the Cryptomatte specification 1.1.0 lays them out:
//! for each type (`CryptoObject`, `CryptoMaterial`) FLOAT channels `{type}00.R/G/B/A`,
//! `{type}01.R/G/B/A`, ... holding (id, coverage) of ranks 0 and 1, 2 and 3, ..., and the
//! header attributes `cryptomatte/<key>/name`, `/hash` (`MurmurHash3_32`), `/conversion`
//! (`uint32_to_float32`) and `/manifest` (JSON, name to the id's float bits in hex), `<key>`
//! being the first 7 hex digits of the MurmurHash3 of the type name.
//!
//! Ids are FLOAT, never half: they are hash bits, and rounding them would name another
//! object. With an odd number of levels the last layer's B and A are id 0, coverage 0.

use ::exr::prelude::{AttributeValue, SmallVec, Text};

use super::layout::ChannelLayout;
use lumis_core::cryptomatte::{CryptoLayer, metadata_key};

/// The channels of `layer` in the lumis layout (`CryptoObject00.R`): (name, values
/// row-major). The EXR writer renames every channel by the layout, these too, which makes them
/// `ViewLayer.CryptoObject00.R` for Blender: the type name [`attributes`] records plus the
/// rank suffix, as readers match them.
pub(super) fn channels(layer: &CryptoLayer) -> Vec<(String, Vec<f32>)> {
    let type_name = layer.name();
    let levels = layer.levels();
    let pixels = layer.ranks().len() / levels;
    let mut out = Vec::new();
    for part in 0..levels.div_ceil(2) {
        for (c, channel) in ["R", "G", "B", "A"].iter().enumerate() {
            let rank = 2 * part + c / 2;
            let values = (0..pixels)
                .map(|i| match layer.pixel(i).get(rank) {
                    Some(r) if c % 2 == 0 => f32::from_bits(r.id),
                    Some(r) => r.coverage,
                    None => 0.0,
                })
                .collect();
            out.push((format!("{type_name}{part:02}.{channel}"), values));
        }
    }
    out
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
