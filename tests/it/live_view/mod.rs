//! `lumis render --display-server` (issue 41): the viewer rebuilds the EXR's pixels exactly,
//! a tile lands at its place in the full image, and a viewer that closes, never reads or is
//! absent changes neither the output bytes nor the exit code (a warning only).

mod receiver;

use crate::common::cli::{assert_ok, binary, run_limited};
use crate::common::exr::read_exr;
use exr::prelude::FlatSamples;
use std::net::{TcpListener, TcpStream};
use std::path::Path;
use std::process::Command;
use std::time::Duration;

/// A small render of the default scene with AOV layers and a pass.
const SCENE: &[&str] = &[
    "--width",
    "72",
    "--height",
    "40",
    "--spp",
    "2",
    "--aov",
    "albedo",
    "--threads",
    "2",
];

fn lumis(dir: &Path, args: &[&str]) -> std::process::Output {
    Command::new(binary())
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

/// The channels of an EXR file as f32, by name, with the data window's place and size.
type FileChannels = (Vec<(String, Vec<f32>)>, (usize, usize), (usize, usize));

/// Every channel of the EXR at `path` (see [`FileChannels`]).
fn exr_channels(path: &Path) -> FileChannels {
    let image = read_exr(path);
    let layer = &image.layer_data[0];
    let pos = layer.attributes.layer_position;
    let size = layer.size;
    let channels = layer
        .channel_data
        .list
        .iter()
        .map(|c| {
            let v = match &c.sample_data {
                FlatSamples::F16(v) => v.iter().map(|h| h.to_f32()).collect(),
                FlatSamples::F32(v) => v.clone(),
                FlatSamples::U32(v) => v.iter().map(|&u| u as f32).collect(),
            };
            (c.name.to_string(), v)
        })
        .collect();
    (channels, (pos.0 as usize, pos.1 as usize), (size.0, size.1))
}

#[test]
fn the_viewer_ends_on_the_exrs_pixels() {
    let dir = tempfile::tempdir().unwrap();
    let (port, viewer) = receiver::start(1);
    let port = port.to_string();
    let mut args = vec!["render", "-o", "live.exr", "--display-server", &port];
    args.extend_from_slice(SCENE);
    let out = lumis(dir.path(), &args);
    assert_ok(&out);
    let got = viewer.join().unwrap();
    let shown = &got.images["live.exr"];
    let (channels, origin, size) = exr_channels(&dir.path().join("live.exr"));
    assert_eq!((shown.width, shown.height, origin), (72, 40, (0, 0)));
    assert_eq!(size, (72, 40));
    // Tiles while rendering (those finished before the connection was made, or while the
    // sender was busy, in one update), then the finished image with the file's channels.
    assert!(shown.rgba_updates >= 1, "{shown:?}");
    assert!(
        shown.updates > shown.rgba_updates,
        "{} updates",
        shown.updates
    );
    assert!(channels.len() > 4, "AOV layers in the file");
    let names: Vec<&String> = shown.channels.keys().collect();
    let mut want: Vec<&String> = channels.iter().map(|(n, _)| n).collect();
    want.sort();
    assert_eq!(names, want);
    for (name, values) in &channels {
        let seen = &shown.channels[name];
        let same = seen
            .iter()
            .zip(values)
            .all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same, "channel {name} differs from the EXR");
    }
    // The same bytes as without the viewer.
    let mut plain = vec!["render", "-o", "plain.exr"];
    plain.extend_from_slice(SCENE);
    assert_ok(&lumis(dir.path(), &plain));
    let live = std::fs::read(dir.path().join("live.exr")).unwrap();
    assert_eq!(live, std::fs::read(dir.path().join("plain.exr")).unwrap());
}

#[test]
fn a_tile_streams_into_the_full_image_at_its_place() {
    let dir = tempfile::tempdir().unwrap();
    let (port, viewer) = receiver::start(1);
    let port = port.to_string();
    let mut args = vec![
        "render",
        "--tile",
        "2/3",
        "-o",
        "t.exr",
        "--display-server",
        &port,
    ];
    args.extend_from_slice(SCENE);
    assert_ok(&lumis(dir.path(), &args));
    let got = viewer.join().unwrap();
    let shown = &got.images["t.exr"];
    let (channels, (x0, y0), (w, h)) = exr_channels(&dir.path().join("t.exr"));
    assert_eq!((shown.width, shown.height), (72, 40), "the full image");
    assert!((w, h) != (72, 40), "a tile is part of the image");
    for (name, values) in &channels {
        let seen = &shown.channels[name];
        for y in 0..40 {
            for x in 0..72 {
                let v = seen[y * 72 + x];
                let inside = (x0..x0 + w).contains(&x) && (y0..y0 + h).contains(&y);
                if inside {
                    let want = values[(y - y0) * w + x - x0];
                    assert_eq!(v.to_bits(), want.to_bits(), "{name} at ({x}, {y})");
                } else {
                    assert_eq!(v, 0.0, "{name} at ({x}, {y}) is outside the tile");
                }
            }
        }
    }
}

/// Renders `SCENE` (bigger, so that the data outgrows the socket buffers) into a viewer that
/// `server` plays, and checks that the outputs are those of a render without one, the exit
/// code 0 and the warning `warning` printed.
fn unaffected_by(port: u16, warning: &str) {
    let dir = tempfile::tempdir().unwrap();
    let scene = [
        "--width", "640", "--height", "480", "--spp", "1", "--aov", "albedo",
    ];
    let port = port.to_string();
    let mut args = vec![
        "render",
        "-o",
        "v.exr",
        "--png",
        "v.png",
        "--display-server",
        &port,
    ];
    args.extend_from_slice(&scene);
    // A hang would fail here rather than stall the test run.
    let run = run_limited(dir.path(), &args, Duration::from_secs(300)).expect("no hang");
    assert!(run.status.success(), "{}", run.stderr);
    assert!(
        run.stderr.contains(warning),
        "no warning `{warning}`:\n{}",
        run.stderr
    );
    let mut plain = vec!["render", "-o", "p.exr", "--png", "p.png"];
    plain.extend_from_slice(&scene);
    assert_ok(&lumis(dir.path(), &plain));
    for (a, b) in [("v.exr", "p.exr"), ("v.png", "p.png")] {
        let a = std::fs::read(dir.path().join(a)).unwrap();
        assert!(
            a == std::fs::read(dir.path().join(b)).unwrap(),
            "{b} differs"
        );
    }
}

#[test]
fn a_viewer_that_closes_mid_render() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    // Each connection: read a little, then close; every reconnection is closed the same way.
    std::thread::spawn(move || {
        for stream in listener.incoming() {
            let mut s = stream.unwrap();
            let mut buf = [0u8; 4096];
            let _ = std::io::Read::read(&mut s, &mut buf);
            drop(s);
        }
    });
    unaffected_by(port, "lost the display server");
}

#[test]
fn a_viewer_that_never_reads() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    let (tx, rx) = std::sync::mpsc::channel::<()>();
    let held = std::thread::spawn(move || {
        let (stream, _) = listener.accept().unwrap();
        // Hold the connection open, reading nothing, until the render is over.
        let _ = rx.recv();
        drop::<TcpStream>(stream);
    });
    // The sender's write times out after a second, as the wait for the finished image does:
    // either may report it first.
    unaffected_by(port, "warning: the display server at");
    tx.send(()).unwrap();
    held.join().unwrap();
}

#[test]
fn no_viewer_at_all() {
    // A port nobody listens on: bound, then closed.
    let port = TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    unaffected_by(port, "could not connect to the display server");
}

#[test]
fn bad_addresses_are_refused_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    for bad in ["", "host:", "0", "99999", "local host:5"] {
        let out = lumis(
            dir.path(),
            &["render", "--display-server", bad, "-o", "x.exr"],
        );
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("[HOST:]PORT"), "{bad}: {err}");
        assert!(!dir.path().join("x.exr").exists());
    }
}
