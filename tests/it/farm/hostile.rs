//! Tiles that were damaged or made by hand: a clean error naming the file, never a panic, a
//! hang or an allocation sized by the file's header.

use std::path::{Path, PathBuf};
use std::time::Duration;

use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Blocks, Compression, Encoding, FlatSamples, Image,
    ImageAttributes, IntegerBounds, Layer, LayerAttributes, LineOrder, SmallVec, Text, Vec2,
    WritableImage,
};

use super::common::cli::run_limited;
use super::common::exr::read_exr;
use super::{merge, refused, render_tiles};

const SIZE: [&str; 4] = ["--width", "16", "--height", "24"];

/// A one-part EXR of `channels` FLOAT channels holding one pixel at (0, 0), marked as tile
/// 0/1 of a `display` image.
fn handmade_tile(path: &Path, display: (usize, usize), channels: usize) {
    handmade_layer(path, display, (1, 1), channels);
}

/// The same with a `layer` pixels data window.
fn handmade_layer(path: &Path, display: (usize, usize), layer: (usize, usize), channels: usize) {
    let pixels = layer.0 * layer.1;
    let mut attributes = LayerAttributes::default();
    attributes.other.insert(
        Text::from("lumis/tile"),
        AttributeValue::Text(Text::from("0/1")),
    );
    let list = (0..channels)
        .map(|i| {
            AnyChannel::new(
                format!("c{i:05}").as_str(),
                FlatSamples::F32(vec![0.5; pixels]),
            )
        })
        .collect();
    let layer = Layer::new(
        Vec2(layer.0, layer.1),
        attributes,
        Encoding {
            compression: Compression::ZIP16,
            blocks: Blocks::ScanLines,
            line_order: LineOrder::Increasing,
        },
        AnyChannels::sort(SmallVec::from_vec(list)),
    );
    let image = Image::new(
        ImageAttributes::new(IntegerBounds::from_dimensions(Vec2(display.0, display.1))),
        layer,
    );
    image.write().to_file(path).unwrap();
}

/// Rewrites the tile at `path` after `edit` changed it.
fn edit_tile(path: &Path, edit: impl FnOnce(&mut Layer<AnyChannels<FlatSamples>>)) {
    let mut image = read_exr(path);
    edit(&mut image.layer_data[0]);
    image.write().to_file(path).unwrap();
}

#[test]
fn headers_that_ask_for_too_much_are_refused_before_decoding() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    handmade_tile(&d.join("wide.exr"), (100_000, 2), 1);
    let err = refused(&merge(d, &[d.join("wide.exr")], "m.exr"));
    assert!(
        err.contains("wide.exr") && err.contains("display window"),
        "{err}"
    );
    handmade_tile(&d.join("many.exr"), (1, 1), 3000);
    let err = refused(&merge(d, &[d.join("many.exr")], "m.exr"));
    assert!(
        err.contains("many.exr") && err.contains("3000 channels"),
        "{err}"
    );
    // A data window larger than the image it is a tile of.
    handmade_layer(&d.join("over.exr"), (4, 4), (64, 2), 1);
    let err = refused(&merge(d, &[d.join("over.exr")], "m.exr"));
    assert!(
        err.contains("over.exr") && err.contains("64x2 data window"),
        "{err}"
    );
    // Right size, but without the tile's finishing attributes.
    handmade_tile(&d.join("bare.exr"), (1, 1), 1);
    let err = refused(&merge(d, &[d.join("bare.exr")], "m.exr"));
    assert!(
        err.contains("bare.exr") && err.contains("lumis/tileBeauty"),
        "{err}"
    );
}

#[test]
fn partial_nan_and_moved_tiles_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let fresh = || -> Vec<PathBuf> {
        let mut t = render_tiles(d, "t", 2, &SIZE);
        t.sort();
        t
    };
    let tiles = fresh();
    edit_tile(&tiles[1], |layer| {
        layer
            .attributes
            .other
            .insert(Text::from("lumis/partial"), AttributeValue::I32(1));
    });
    let err = refused(&merge(d, &tiles, "m.exr"));
    assert!(err.contains("t_1.exr") && err.contains("partial"), "{err}");

    let tiles = fresh();
    edit_tile(&tiles[0], |layer| {
        let n = layer
            .channel_data
            .list
            .iter_mut()
            .find(|c| c.name == *"N.X")
            .unwrap();
        if let FlatSamples::F32(v) = &mut n.sample_data {
            v[3] = f32::NAN;
        }
    });
    let err = refused(&merge(d, &tiles, "m.exr"));
    assert!(
        err.contains("t_0.exr") && err.contains("N.X holds NaN"),
        "{err}"
    );

    let tiles = fresh();
    edit_tile(&tiles[1], |layer| {
        layer.attributes.layer_position = Vec2(0, 11)
    });
    let err = refused(&merge(d, &tiles, "m.exr"));
    assert!(
        err.contains("t_1.exr") && err.contains("holds pixels"),
        "{err}"
    );
    assert!(!d.join("m.exr").exists());
}

/// Seeded byte flips anywhere in a real tile: the merge either succeeds or fails cleanly,
/// within a time limit.
#[test]
fn mutated_tiles_fail_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut tiles = render_tiles(d, "t", 2, &SIZE);
    tiles.sort();
    let bytes = std::fs::read(&tiles[0]).unwrap();
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let mutant = d.join("mutant.exr");
    for case in 0..120 {
        let mut m = bytes.clone();
        for _ in 0..1 + next() % 4 {
            // Half the flips in the header, where the sizes are.
            let limit = if next() % 2 == 0 {
                400.min(m.len())
            } else {
                m.len()
            };
            let at = (next() % limit as u64) as usize;
            m[at] ^= 1 << (next() % 8);
        }
        std::fs::write(&mutant, &m).unwrap();
        let args = [
            "merge",
            "-q",
            "-o",
            "m.exr",
            "mutant.exr",
            tiles[1].to_str().unwrap(),
        ];
        let run = run_limited(d, &args, Duration::from_secs(30))
            .unwrap_or_else(|| panic!("case {case}: the merge hung"));
        assert!(
            matches!(run.status.code(), Some(0) | Some(1)) && !run.stderr.contains("panicked"),
            "case {case}: {:?} {}",
            run.status,
            run.stderr
        );
        if run.status.code() == Some(1) {
            assert!(
                run.stderr.contains("mutant.exr"),
                "case {case}: {}",
                run.stderr
            );
        }
    }
}
