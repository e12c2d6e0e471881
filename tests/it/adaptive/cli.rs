//! `--adaptive`, `render.adaptive` and `-D render.adaptive` through the binary: bad values
//! refused by name, the samples AOV written, the skipped rays in `--stats-json`, and farm
//! tiles of different thresholds refused by merge while tiles of one threshold merge into the
//! single render's bytes.

use crate::common::cli::assert_ok;
use crate::common::exr::{channel, read_exr};
use crate::farm::{lumis, merge, refused, render_full, render_tiles};

const SIZE: [&str; 4] = ["--width", "24", "--height", "40"];

#[test]
fn bad_thresholds_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (args, expected) in [
        (
            vec!["--adaptive=-1"],
            "--adaptive: adaptive threshold -1 must be finite",
        ),
        (
            vec!["--adaptive", "nan"],
            "adaptive threshold NaN must be finite",
        ),
        (
            vec!["-D", "render.adaptive=-0.5"],
            "adaptive threshold -0.5 must be finite",
        ),
        (vec!["-D", "render.adaptive=\"x\""], "adaptive"),
    ] {
        let mut all = vec!["render", "-q", "-o", "x.exr"];
        all.extend_from_slice(&SIZE);
        all.extend_from_slice(&args);
        let err = refused(&lumis(d, &all));
        assert!(err.contains(expected), "{args:?}: {err}");
        assert!(!d.join("x.exr").exists());
    }
}

#[test]
fn samples_aov_and_stats_report_the_skipped_samples() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut args = vec![
        "render",
        "-q",
        "-o",
        "a.exr",
        "--spp",
        "3",
        "-D",
        "render.adaptive=0.1",
        "--aov",
        "samples",
        "--stats-json",
        "stats.json",
    ];
    args.extend_from_slice(&SIZE);
    assert_ok(&lumis(d, &args));
    let image = read_exr(&d.join("a.exr"));
    let samples = channel(&image, "samples");
    assert_eq!(samples.len(), 24 * 40);
    assert!(samples.iter().all(|&s| s == 4.0 || s == 9.0), "{samples:?}");
    let kept = samples.iter().filter(|&&s| s == 4.0).count() as u64;
    assert!(kept > 0);
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("stats.json")).unwrap()).unwrap();
    let text = stats.to_string();
    assert!(text.contains("\"adaptive\""), "{text}");
    // The default scene has depth of field: one lens ray a sample.
    let found = find_key(&stats, "adaptive").expect("adaptive count");
    assert_eq!(found, serde_json::json!(5 * kept));
}

/// The first value under `key` anywhere in `v`.
fn find_key(v: &serde_json::Value, key: &str) -> Option<serde_json::Value> {
    match v {
        serde_json::Value::Object(m) => m
            .get(key)
            .filter(|x| x.is_number())
            .cloned()
            .or_else(|| m.values().find_map(|x| find_key(x, key))),
        serde_json::Value::Array(a) => a.iter().find_map(|x| find_key(x, key)),
        _ => None,
    }
}

#[test]
fn tiles_merge_to_the_single_render_and_other_thresholds_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut args = vec!["--adaptive", "0.05", "--spp", "3", "--aov", "samples"];
    args.extend_from_slice(&SIZE);
    let single = std::fs::read(render_full(d, "ad", &args)).unwrap();
    let mut tiles = render_tiles(d, "ad", 3, &args);
    tiles.sort();
    assert_ok(&merge(d, &tiles, "merged.exr"));
    assert!(std::fs::read(d.join("merged.exr")).unwrap() == single);
    // A tile of the same render at another threshold, and one without adaptive sampling.
    for (other, expected) in [
        (
            vec!["--adaptive", "0.1"],
            "render.adaptive: 0.1 against 0.05",
        ),
        (vec![], "render.adaptive: absent against 0.05"),
    ] {
        let mut a = vec!["render", "-q", "--tile", "1/3", "-o", "foreign.exr"];
        a.extend_from_slice(&["--spp", "3", "--aov", "samples"]);
        a.extend_from_slice(&SIZE);
        a.extend_from_slice(&other);
        assert_ok(&lumis(d, &a));
        let err = refused(&merge(
            d,
            &[tiles[0].clone(), d.join("foreign.exr"), tiles[2].clone()],
            "m.exr",
        ));
        assert!(
            err.contains("foreign.exr") && err.contains(expected),
            "{err}"
        );
    }
}
