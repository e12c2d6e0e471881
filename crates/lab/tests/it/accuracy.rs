//! `lumis-lab accuracy` at a tiny size on the default scene and the far hard case: the CSV
//! has every knob, the reference's error is zero, more samples lower the error, the fast
//! precision disagrees with float64 brute force far from the origin, and the plot is written.
//! Nothing here looks at times: speed is measured by the benchmark itself.

use crate::common;

use std::collections::HashMap;
use std::process::Command;

#[test]
fn bench_accuracy_writes_csv_and_plot_with_meaningful_errors() {
    let dir = tempfile::tempdir().unwrap();
    let (csv, plot) = (dir.path().join("acc.csv"), dir.path().join("acc.svg"));
    let out = Command::new(env!("CARGO_BIN_EXE_lumis-lab"))
        .args(["accuracy", "default", "far-occluder"])
        .args(["--width", "64", "--height", "36", "--rounds", "1", "--csv"])
        .arg(&csv)
        .arg("--plot")
        .arg(&plot)
        .output()
        .unwrap();
    common::cli::assert_ok(&out);
    assert!(
        std::fs::metadata(&plot).unwrap().len() > 1000,
        "plot too small"
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let get = |scene: &str, knob: &str, value: &str| -> HashMap<&str, f64> {
        let r = rows
            .iter()
            .find(|r| r[0] == scene && r[1] == knob && r[2] == value)
            .unwrap_or_else(|| panic!("no row {scene} {knob} {value}"));
        header
            .iter()
            .enumerate()
            .filter_map(|(i, h)| r[i].parse().ok().map(|v| (*h, v)))
            .collect()
    };
    for scene in ["default", "far-occluder"] {
        for knob in [
            "default",
            "spp",
            "max_depth",
            "cutoff",
            "precision",
            "offset",
            "corner",
            "reference",
        ] {
            assert!(
                rows.iter().any(|r| r[0] == scene && r[col("knob")] == knob),
                "{scene}: no {knob} rows"
            );
        }
        let reference = get(scene, "reference", "reference");
        assert!(reference["rmse"] < 1e-9 && reference["rel_mse"] < 1e-9);
        assert_eq!(reference["ray_hit_miss"] + reference["ray_prim"], 0.0);
        let (one, four) = (get(scene, "spp", "1"), get(scene, "spp", "4"));
        assert!(
            four["rel_mse"] < one["rel_mse"] && four["rmse"] < one["rmse"],
            "{scene}: 4 spp {four:?} vs 1 spp {one:?}"
        );
    }
    let fast = get("far-occluder", "precision", "fast");
    let disagreements = fast["ray_hit_miss"] + fast["ray_prim"] + fast["shadow_disagree"];
    assert!(
        disagreements > 0.0,
        "fast agrees with f64 everywhere: {fast:?}"
    );
    // The fixed-ulp offset lifts shadow rays over the occluder hovering 0.5 above the ground.
    assert!(get("far-occluder", "offset", "ulp")["shadow_disagree"] > 0.0);
}
