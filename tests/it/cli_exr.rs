//! The compositing flags end to end through the binary: `--crop` / `--pixel-bounds` write a
//! data window whose pixels are the full render's, `--z-miss` sets the depth of misses, and
//! Ctrl-C during a render writes the finished tiles as a valid partial EXR and exits 130; the
//! same input gives the same bytes for any thread count.

use std::path::Path;
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use exr::prelude::{AttributeValue, Text, Vec2};

use crate::common;
use common::exr::{channel, read_exr};

fn lumis(dir: &Path) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_lumis"));
    c.current_dir(dir);
    c
}

fn ok(out: Output) {
    common::cli::assert_ok(&out);
}

const SIZE: [&str; 8] = [
    "--width", "40", "--height", "24", "--spp", "1", "--float", "--quiet",
];

#[test]
fn crop_and_pixel_bounds_write_a_data_window_of_the_full_render() {
    let dir = tempfile::tempdir().unwrap();
    ok(lumis(dir.path())
        .args(SIZE)
        .args(["-o", "full.exr"])
        .output()
        .unwrap());
    // pbrt's rule: ceil(40 * 0.3) = 12, ceil(40 * 0.75) = 30, ceil(24 * 0.1) = 3, 24.
    ok(lumis(dir.path())
        .args(SIZE)
        .args(["-o", "crop.exr", "--crop", "0.3,0.75,0.1,1"])
        .output()
        .unwrap());
    ok(lumis(dir.path())
        .args(SIZE)
        .args(["-o", "bounds.exr", "--pixel-bounds", "12,30,3,24"])
        .output()
        .unwrap());
    let full = read_exr(&dir.path().join("full.exr"));
    let full_r = channel(&full, "R");
    for name in ["crop.exr", "bounds.exr"] {
        let part = read_exr(&dir.path().join(name));
        let layer = &part.layer_data[0];
        assert_eq!(layer.size, Vec2(18, 21), "{name}");
        assert_eq!(layer.attributes.layer_position, Vec2(12, 3), "{name}");
        assert_eq!(part.attributes.display_window.size, Vec2(40, 24), "{name}");
        let r = channel(&part, "R");
        for y in 0..21 {
            for x in 0..18 {
                let want = full_r[(y + 3) * 40 + x + 12];
                assert_eq!(r[y * 18 + x].to_bits(), want.to_bits(), "{name} ({x}, {y})");
            }
        }
    }
}

#[test]
fn bad_windows_are_refused_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    for (flag, value, want) in [
        ("--crop", "0.5,0.2,0,1", "x0 < x1"),
        ("--crop", "0,1.2,0,1", "[0, 1]"),
        ("--pixel-bounds", "0,50,0,10", "outside the 40x24 image"),
        ("--z-miss", "-1", "positive finite"),
    ] {
        let out = lumis(dir.path())
            .args(SIZE)
            .args([flag, value])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(want),
            "{flag} {value}: {err}"
        );
        assert!(
            std::fs::read_dir(dir.path()).unwrap().next().is_none(),
            "output left"
        );
    }
}

#[test]
fn z_miss_replaces_infinite_depth() {
    let dir = tempfile::tempdir().unwrap();
    ok(lumis(dir.path())
        .args(SIZE)
        .args(["-o", "inf.exr"])
        .output()
        .unwrap());
    ok(lumis(dir.path())
        .args(SIZE)
        .args(["-o", "big.exr", "--z-miss", "1e10"])
        .output()
        .unwrap());
    let (inf, big) = (
        channel(&read_exr(&dir.path().join("inf.exr")), "Z"),
        channel(&read_exr(&dir.path().join("big.exr")), "Z"),
    );
    let misses = inf.iter().filter(|z| z.is_infinite()).count();
    assert!(misses > 0, "the default scene shows background at the top");
    for (a, b) in inf.iter().zip(&big) {
        let want = if a.is_infinite() { 1e10 } else { *a };
        assert_eq!(b.to_bits(), want.to_bits());
    }
}

#[cfg(unix)]
#[test]
fn ctrl_c_writes_the_finished_tiles_as_a_partial_exr_and_exits_130() {
    let dir = tempfile::tempdir().unwrap();
    // Large enough to take far longer than the wait below on any machine.
    let mut child = lumis(dir.path())
        .args([
            "--width", "1600", "--height", "1600", "--spp", "12", "--float",
        ])
        .args(["-o", "part.exr", "--quiet"])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    std::thread::sleep(Duration::from_millis(2500));
    assert!(
        child.try_wait().unwrap().is_none(),
        "the render ended before the interrupt"
    );
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "stderr: {err}");
    assert!(err.contains("interrupted"), "{err}");
    assert!(
        start.elapsed() < Duration::from_secs(60),
        "it stopped promptly"
    );
    let image = read_exr(&dir.path().join("part.exr"));
    let partial = image.layer_data[0]
        .attributes
        .other
        .get(&Text::from("lumis/partial"))
        .cloned();
    assert_eq!(partial, Some(AttributeValue::I32(1)));
    let a = channel(&image, "A");
    let done = a.iter().filter(|&&v| v > 0.0).count();
    assert!(done > 0, "some tiles were finished");
    assert!(done < a.len(), "some tiles were not: their alpha is 0");
}

#[test]
fn same_input_same_bytes_for_any_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    for (threads, name) in [("1", "a.exr"), ("2", "b.exr"), ("3", "c.exr")] {
        ok(lumis(dir.path())
            .args(SIZE)
            .args(["--threads", threads, "-o", name])
            .output()
            .unwrap());
    }
    let a = std::fs::read(dir.path().join("a.exr")).unwrap();
    for name in ["b.exr", "c.exr"] {
        assert!(
            a == std::fs::read(dir.path().join(name)).unwrap(),
            "{name} differs"
        );
    }
    // The render time only on request: then it is there.
    ok(lumis(dir.path())
        .args(SIZE)
        .args(["--timing-metadata", "-o", "t.exr"])
        .output()
        .unwrap());
    let t = read_exr(&dir.path().join("t.exr"));
    let other = &t.layer_data[0].attributes.other;
    assert!(other.contains_key(&Text::from("lumis/renderSeconds")));
    assert!(
        !read_exr(&dir.path().join("a.exr")).layer_data[0]
            .attributes
            .other
            .contains_key(&Text::from("lumis/renderSeconds"))
    );
}
