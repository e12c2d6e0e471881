//! Bad `[[instance]]` tables are refused naming the table and the key, never by a panic.

use std::time::Instant;

use super::error;

const BALL: &str = "[[sphere]]\nname = \"ball\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\n\n\
                    [[mesh]]\npositions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\nindices = [[0, 1, 2]]\n";

/// The error loading `BALL` with a second instance table `table` (after a good one).
fn second(table: &str) -> String {
    error(
        &format!("{BALL}\n[[instance]]\nof = \"ball\"\n\n[[instance]]\nname = \"bad\"\n{table}\n"),
        &[],
    )
}

#[test]
fn bad_instance_tables_name_the_table_and_the_key() {
    let cases = [
        (
            "of = \"nope\"",
            "instance[1] \"bad\": of = \"nope\": no [[mesh]] or [[sphere]] has that name (named: [\"ball\", \"mesh0\"])",
        ),
        (
            "of = \"ball\"\nscale = [1.0, 0.0, 1.0]",
            "instance[1] \"bad\": scale [1.0, 0.0, 1.0] must be non-zero",
        ),
        (
            "of = \"ball\"\ntranslations = [[0, 0, 0], [1, 0, 0]]\nscales = [1.0]",
            "instance[1] \"bad\": scales has 1 entries but translations has 2",
        ),
        (
            "of = \"mesh0\"\nmatrix = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\ntranslate = [1, 0, 0]",
            "instance[1] \"bad\": matrix is the whole placement: give it without translate, rotate or scale",
        ),
        (
            "of = \"ball\"\ntranslate = [0.0, inf, 0.0]",
            "instance[1] \"bad\": translate [0.0, inf, 0.0] must be finite",
        ),
        (
            "of = \"ball\"\ntranslations = [[0, 0, 0], [0, nan, 0]]",
            "instance[1] \"bad\": translations[1] [0.0, NaN, 0.0] must be finite",
        ),
        (
            "of = \"ball\"\nmatrix = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1]",
            "instance[1] \"bad\": matrix: the transform is singular",
        ),
        (
            "of = \"ball\"\ntranslate = [1e30, 0.0, 0.0]",
            "instance \"bad\"",
        ),
    ];
    for (table, expected) in cases {
        let e = second(table);
        assert!(
            e.starts_with("scene.toml: ") && e.contains(expected),
            "{table}:\n{e}\nexpected {expected}"
        );
    }
    // Schema errors keep their line: `of` is required.
    let e = second("translate = [1.0, 0.0, 0.0]");
    assert!(
        e.contains("line ") && e.contains("missing field `of`"),
        "{e}"
    );
}

#[test]
fn too_many_placements_are_refused_before_they_are_made() {
    let entries = vec!["[0,0,0]"; lumis_io::formats::toml::MAX_INSTANCE_OBJECTS + 1].join(",");
    let text = format!("{BALL}\n[[instance]]\nof = \"ball\"\ntranslations = [{entries}]\n");
    let start = Instant::now();
    let e = error(&text, &[]);
    eprintln!("{} MB refused in {:?}", text.len() >> 20, start.elapsed());
    assert!(
        e.contains("instance[0]: translations has 1000001 entries; a scene places at most 1000000"),
        "{e}"
    );
}

#[test]
fn the_cli_refuses_an_unknown_prototype_with_exit_status_not_zero() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("scene.toml"),
        format!("{BALL}\n[[instance]]\nof = \"bal\"\n"),
    )
    .unwrap();
    let out = std::process::Command::new(crate::common::cli::binary())
        .args(["render", "scene.toml", "-o", "out.exr"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_ne!(out.status.code(), Some(0), "{stderr}");
    assert!(
        stderr.contains(
            "scene.toml: instance[0]: of = \"bal\": no [[mesh]] or [[sphere]] has that name"
        ),
        "{stderr}"
    );
    assert!(!dir.path().join("out.exr").exists());
}
