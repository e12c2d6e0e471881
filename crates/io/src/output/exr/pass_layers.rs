//! The RGB pass layers of the film (`--aov lightpaths`, `--aov lights`, a shadow catcher's
//! `shadow`), all FLOAT, box-filtered over the pixel's samples like the beauty:
//!
//! | channel                 | content                                                       |
//! |-------------------------|---------------------------------------------------------------|
//! | `diffuse.R/G/B`         | direct light on the diffuse lobe at the first hit             |
//! | `specular.*`            | direct Phong highlights at the first hit                      |
//! | `reflection.*`          | everything seen through the first hit's mirror ray            |
//! | `refraction.*`          | everything seen through the first hit's refracted ray         |
//! | `emission.*`            | the first hit's emission                                      |
//! | `ambient.*`             | the first hit's ambient term (the environment's diffuse part) |
//! | `background.*`          | escaping camera rays (and the background behind a catcher)    |
//! | `light.<name>.*`        | one light's direct diffuse + specular at the first hit        |
//! | `shadow.*`              | what a plate behind a shadow catcher is multiplied by (1: lit) |
//!
//! The seven light paths add up to the beauty's R, G, B and the lights to diffuse + specular
//! (`lumis_core::integrator::paths`). Blender's names are in `layout.rs`.

use std::collections::BTreeSet;

use super::layout::ChannelLayout;
use lumis_core::film::{Film, SHADOW_PASS};
use lumis_core::integrator::LightPaths;

const RGB: [&str; 3] = ["R", "G", "B"];

/// The pass channels of `film`, as (lumis name, values row-major).
pub(super) fn channels(film: &Film) -> Vec<(String, Vec<f32>)> {
    film.passes()
        .iter()
        .flat_map(|pass| {
            RGB.iter().enumerate().map(move |(c, letter)| {
                (
                    format!("{}.{letter}", pass.name()),
                    pass.values().iter().map(|v| v[c]).collect(),
                )
            })
        })
        .collect()
}

/// The lumis names of the pass layers in a file with channels `names` (in `layout`): each
/// layer whose `R` channel is there, in name order.
pub(super) fn present(layout: ChannelLayout, names: &BTreeSet<String>) -> Vec<String> {
    names
        .iter()
        .filter_map(|name| lumis_layer(layout, name))
        .collect()
}

/// The lumis pass layer whose `R` channel is called `channel` in `layout`, if any.
fn lumis_layer(layout: ChannelLayout, channel: &str) -> Option<String> {
    let fixed = LightPaths::NAMES
        .iter()
        .chain(&[SHADOW_PASS])
        .map(|n| n.to_string());
    let light = match layout {
        ChannelLayout::Lumis => channel
            .strip_prefix("light.")
            .and_then(|rest| rest.strip_suffix(".R"))
            .map(|n| format!("light.{n}")),
        ChannelLayout::Blender => channel
            .strip_prefix("ViewLayer.Combined_")
            .and_then(|rest| rest.strip_suffix(".R"))
            .map(|n| format!("light.{n}")),
    };
    fixed
        .chain(light)
        .find(|layer| layout.channel(&format!("{layer}.R")) == channel)
}

/// Every channel (lumis names) of the pass layers `layers`.
pub(super) fn names(layers: &[String]) -> Vec<String> {
    layers
        .iter()
        .flat_map(|l| RGB.iter().map(move |c| format!("{l}.{c}")))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layers_are_found_back_from_their_channels_in_both_layouts() {
        for layout in ChannelLayout::ALL {
            let layers = ["diffuse", "ambient", "light.key_2", "shadow", "background"];
            let names: BTreeSet<String> = layers
                .iter()
                .flat_map(|l| RGB.map(|c| layout.channel(&format!("{l}.{c}"))))
                .chain(["R", "id.object", "albedo.R"].map(|c| layout.channel(c)))
                .collect();
            let mut want: Vec<String> = layers.iter().map(|s| s.to_string()).collect();
            want.sort_by_key(|l| layout.channel(&format!("{l}.R")));
            assert_eq!(present(layout, &names), want, "{layout:?}");
        }
    }
}
