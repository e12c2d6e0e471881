//! Reading lumis's EXR files back with the exr crate (an independent reader), for the tests
//! that assert on channels and header attributes.

use std::path::Path;

use exr::prelude::{AnyChannels, FlatSamples, Image, Layers, ReadChannels, ReadLayers, read};

/// Every layer, channel and attribute of a file, samples as stored.
pub type FlatImage = Image<Layers<AnyChannels<FlatSamples>>>;

/// The whole file at `path` (panics if it does not read).
pub fn read_exr(path: &Path) -> FlatImage {
    read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_file(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// FLOAT channel `name` of the first layer, row-major (panics if missing or not FLOAT).
pub fn channel(image: &FlatImage, name: &str) -> Vec<f32> {
    let layer = &image.layer_data[0];
    let c = layer.channel_data.list.iter().find(|c| c.name == *name);
    match &c.unwrap_or_else(|| panic!("no channel {name}")).sample_data {
        FlatSamples::F32(v) => v.clone(),
        other => panic!("{name} is not FLOAT: {other:?}"),
    }
}

/// The channel names of the first layer, in the file's order.
pub fn channel_names(image: &FlatImage) -> Vec<String> {
    image.layer_data[0]
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect()
}
