//! §4: `lumis-lab effects` measures both modes on the same scene and reports what it saw.

use super::measure::{csv, markdown, measure_effects, reasons_markdown};

#[test]
fn bench_effects_measures_both_modes_and_reports_identical_images() {
    let mut scene = lumis_io::formats::default_scene().expect("default scene");
    let st = scene.settings_mut();
    (st.width, st.height, st.spp, st.cutoff) = (32, 18, 1, 0.0);
    let row = measure_effects(&scene, "default", 1, Some(1), false).expect("bench");
    assert!(row.identical, "cutoff 0: the images must agree");
    assert!(row.all.total() > row.auto.total());
    assert_eq!(
        (row.auto.aov, row.all.aov),
        (0, 32 * 18),
        "PNG-only vs reference"
    );
    assert!(row.auto_seconds > 0.0 && row.all_seconds > 0.0);
    let table = markdown(std::slice::from_ref(&row));
    assert!(
        table
            .lines()
            .nth(2)
            .is_some_and(|l| l.starts_with("| default |") && l.ends_with("| yes |"))
    );
    assert!(reasons_markdown(std::slice::from_ref(&row)).contains("| default |"));
    assert_eq!(csv(&[row]).lines().count(), 2);
}
