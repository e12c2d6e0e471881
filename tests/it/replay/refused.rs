//! What `--from` and `lumis merge` refuse, and the words they refuse it with.

use super::lumis;
use crate::common::cli::assert_ok;
use crate::common::exr::read_exr;
use exr::prelude::{AttributeValue, Text, WritableImage};
use std::path::Path;

/// Renders the default scene with `extra` into `dir/NAME`.
fn render(dir: &Path, name: &str, extra: &[&str]) {
    let mut args = vec![
        "render", "-q", "--width", "24", "--height", "16", "-o", name,
    ];
    args.extend_from_slice(extra);
    assert_ok(&lumis(dir, &args));
}

/// Sets the string attribute `name` of the EXR at `path` to `value`.
fn set_attribute(path: &Path, name: &str, value: &str) {
    let mut image = read_exr(path);
    image.layer_data[0]
        .attributes
        .other
        .insert(Text::from(name), AttributeValue::Text(Text::from(value)));
    image.write().to_file(path).unwrap();
}

/// `lumis ARGS` fails, with `words` in its message.
fn refused_with(dir: &Path, args: &[&str], words: &[&str]) {
    let out = lumis(dir, args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} ran");
    for w in words {
        assert!(err.contains(w), "{args:?}: no `{w}` in:\n{err}");
    }
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn a_changed_or_missing_input() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("sphere.toml");
    let text = "[[sphere]]\ncenter = [0.0, 0.0, -3.0]\nradius = 1.0\n\n[[light]]\ntype = \"point\"\nposition = [2.0, 2.0, 0.0]\nintensity = 10.0\n";
    std::fs::write(&scene, text).unwrap();
    render(dir.path(), "a.exr", &["sphere.toml"]);
    std::fs::write(&scene, format!("{text}# edited\n")).unwrap();
    refused_with(
        dir.path(),
        &["render", "--from", "a.exr", "-o", "b.exr"],
        &["a.exr", "sphere.toml", "changed"],
    );
    // A header that names a device as an input: refused, never read (it would never end).
    let image = dir.path().join("a.exr");
    let mut exr = read_exr(&image);
    let replay = r#"{"inputs":{"/dev/zero":"00"},"scene":"sphere.toml"}"#;
    exr.layer_data[0].attributes.other.insert(
        Text::from("lumis/replay"),
        AttributeValue::Text(Text::from(replay)),
    );
    exr.write().to_file(dir.path().join("dev.exr")).unwrap();
    refused_with(
        dir.path(),
        &["render", "--from", "dev.exr", "-o", "b.exr"],
        &["dev.exr", "/dev/zero", "not a regular file"],
    );
    std::fs::remove_file(&scene).unwrap();
    refused_with(
        dir.path(),
        &["render", "--from", "a.exr", "-o", "b.exr"],
        &["a.exr", "sphere.toml", "cannot be read"],
    );
    assert!(!dir.path().join("b.exr").exists());
}

#[test]
fn another_version_an_old_record_and_added_flags() {
    let dir = tempfile::tempdir().unwrap();
    render(dir.path(), "a.exr", &[]);
    refused_with(
        dir.path(),
        &["render", "--from", "a.exr", "--spp", "3", "-o", "b.exr"],
        &["a.exr", "--spp", "cannot be added"],
    );
    let path = dir.path().join("a.exr");
    set_attribute(&path, "lumis/renderer", "lumis 0.0.1");
    refused_with(
        dir.path(),
        &["render", "--from", "a.exr", "-o", "b.exr"],
        &[
            "a.exr",
            "made by lumis 0.0.1",
            concat!("this is lumis ", env!("CARGO_PKG_VERSION")),
        ],
    );
    render(dir.path(), "old.exr", &[]);
    set_attribute(
        &dir.path().join("old.exr"),
        "lumis/settings",
        "width: 24\nheight: 16",
    );
    refused_with(
        dir.path(),
        &["render", "--from", "old.exr", "-o", "b.exr"],
        &["old.exr", "text record of an older lumis"],
    );
}

#[test]
fn the_merge_refuses_a_tile_with_the_old_text_record() {
    let dir = tempfile::tempdir().unwrap();
    for i in 0..2 {
        render(
            dir.path(),
            &format!("t{i}.exr"),
            &["--tile", &format!("{i}/2")],
        );
    }
    set_attribute(
        &dir.path().join("t1.exr"),
        "lumis/settings",
        "width: 24\nheight: 16",
    );
    refused_with(
        dir.path(),
        &["merge", "t0.exr", "t1.exr", "-o", "m.exr"],
        &["t1.exr", "text record of an older lumis"],
    );
}
