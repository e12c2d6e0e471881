//! What a frame changes in the outputs: `#` runs in the file names become the frame number,
//! and the EXR header records the frame, the rate and the SMPTE time code.

use exr::prelude::{AttributeValue, Text};
use lumis_io::output::ATTR_FRAME;

use super::common::exr::{FlatImage, read_exr};
use super::{CAMERA_KEYS, STILL, animated, render};

#[test]
fn hashes_in_the_outputs_become_the_padded_frame_number() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("out")).unwrap();
    let scene = animated(12, CAMERA_KEYS);
    let png = ["--png", "p_##.png"];
    render(
        d,
        "a.toml",
        &scene,
        "out/f_####.exr",
        &[&png[..], &["--frame", "7"]].concat(),
    );
    // An animated scene without --frame is its frame 0, numbered as such.
    render(d, "a.toml", &scene, "out/f_####.exr", &[]);
    // A number longer than the run is written whole.
    render(d, "a.toml", &scene, "out/g_#.exr", &["--frame", "11"]);
    // A still has no frame number: its # stay as written.
    render(d, "s.toml", STILL, "out/s_##.exr", &[]);
    let names = super::common::files::dir_entries(&d.join("out"));
    assert_eq!(names, ["f_0000.exr", "f_0007.exr", "g_11.exr", "s_##.exr"]);
    assert!(d.join("p_07.png").is_file());
}

/// The header's frame attributes: `lumis/frame`, `framesPerSecond`, `timeCode` (h, m, s, f).
type FrameAttributes = (
    Option<AttributeValue>,
    Option<(i32, u32)>,
    Option<(u8, u8, u8, u8)>,
);

fn frame_attributes(image: &FlatImage) -> FrameAttributes {
    let layer = &image.layer_data[0].attributes;
    (
        layer.other.get(&Text::from(ATTR_FRAME)).cloned(),
        layer.frames_per_second,
        image
            .attributes
            .time_code
            .map(|t| (t.hours, t.minutes, t.seconds, t.frame)),
    )
}

#[test]
fn the_header_records_the_frame_the_rate_and_the_time_code() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let read = |scene: &str, args: &[&str]| {
        render(d, "a.toml", scene, "h.exr", args);
        frame_attributes(&read_exr(&d.join("h.exr")))
    };
    let frame = |n: i32| Some(AttributeValue::I32(n));
    let film = animated(100, CAMERA_KEYS);
    assert_eq!(
        read(&film, &["--frame", "7"]),
        (frame(7), Some((24, 1)), Some((0, 0, 0, 7)))
    );
    assert_eq!(
        read(&film, &["--frame", "75"]),
        (frame(75), Some((24, 1)), Some((0, 0, 3, 3)))
    );
    // NTSC rates have no exact non-drop time code; over 30 fps SMPTE has none.
    let ntsc = film.replace("frames = 100", "frames = 100\nfps = [24000, 1001]");
    assert_eq!(
        read(&ntsc, &["--frame", "7"]),
        (frame(7), Some((24000, 1001)), None)
    );
    let fast = film.replace("frames = 100", "frames = 100\nfps = 60");
    assert_eq!(
        read(&fast, &["--frame", "7"]),
        (frame(7), Some((60, 1)), None)
    );
    assert_eq!(read(STILL, &[]), (None, None, None));
}
