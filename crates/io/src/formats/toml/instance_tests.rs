//! Placements of `[[instance]]` tables: the transform convention and the checks.

use super::*;

fn doc(text: &str) -> InstanceDoc {
    ::toml::from_str(&format!("of = \"x\"\n{text}")).unwrap()
}

fn one(text: &str) -> Result<DAffine3, String> {
    let d = doc(text);
    placement_count(&d)?;
    Ok(placements(&d, "a")?.remove(0).1)
}

#[test]
fn a_placement_scales_then_rotates_x_y_z_then_translates() {
    let a = one("translate = [1, 2, 3]\nrotate = [90, 0, 0]\nscale = [2, 1, 1]").unwrap();
    let p = a.transform_point3(DVec3::new(1.0, 1.0, 0.0));
    // (1, 1, 0) -> scaled (2, 1, 0) -> rotated 90 about X (2, 0, 1) -> moved (3, 2, 4).
    assert!((p - DVec3::new(3.0, 2.0, 4.0)).length() < 1e-12, "{p}");
    let r = one("rotate = [0, 90, 90]").unwrap();
    // About Y first: X goes to -Z, which Z's rotation leaves alone.
    let x = r.transform_vector3(DVec3::X);
    assert!((x - DVec3::NEG_Z).length() < 1e-12, "{x}");
}

#[test]
fn a_matrix_is_row_major_with_the_translation_in_the_last_column() {
    let m = one("matrix = [0, -1, 0, 5,  1, 0, 0, 6,  0, 0, 2, 7,  0, 0, 0, 1]").unwrap();
    let p = m.transform_point3(DVec3::new(1.0, 0.0, 1.0));
    assert_eq!(p, DVec3::new(5.0, 7.0, 9.0));
}

#[test]
fn arrays_name_one_placement_per_entry() {
    let d = doc("translations = [[0, 0, 0], [1, 0, 0], [2, 0, 0]]\nscales = [1, 2, [1, 1, 3]]");
    assert_eq!(placement_count(&d), Ok(3));
    let p = placements(&d, "row").unwrap();
    let names: Vec<&str> = p.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["row/0", "row/1", "row/2"]);
    assert_eq!(p[2].1.transform_point3(DVec3::Z), DVec3::new(2.0, 0.0, 3.0));
    assert_eq!(p[1].1.transform_point3(DVec3::X), DVec3::new(3.0, 0.0, 0.0));
}

#[test]
fn bad_placements_name_the_key_and_what_was_expected() {
    let err = |text: &str| one(text).unwrap_err();
    assert!(err("scale = [1, 0, 1]").contains("scale [1.0, 0.0, 1.0] must be non-zero"));
    assert!(err("scale = 0").contains("non-zero"));
    assert!(err("translate = [1, nan, 0]").contains("translate [1.0, NaN, 0.0] must be finite"));
    assert!(err("rotate = [inf, 0, 0]").contains("rotate"));
    let e = err("translations = [[0, 0, 0], [1, 1, 1]]\nrotations = [[0, 0, 0]]");
    assert!(
        e.contains("rotations has 1 entries but translations has 2"),
        "{e}"
    );
    let e = err("translations = [[0, 0, 0], [1, 1, 1]]\nscales = [1, 0]");
    assert!(
        e.contains("scales[1] [0.0, 0.0, 0.0] must be non-zero"),
        "{e}"
    );
    let e = err("translations = [[0, 0, 0]]\ntranslate = [1, 1, 1]");
    assert!(e.contains("give one or the other"), "{e}");
    assert!(err("rotations = [[0, 0, 0]]").contains("go with translations"));
    assert!(err("translations = []").contains("empty"));
    let e = err("matrix = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\ntranslate = [1, 0, 0]");
    assert!(e.contains("matrix is the whole placement"), "{e}");
    assert!(err("matrix = [1, 0, 0]").contains("matrix has 3 numbers: expected 16"));
    let e = err("matrix = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1]");
    assert!(e.contains("last row is [1.0, 0.0, 0.0, 1.0]"), "{e}");
    let e = err("matrix = [1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]");
    assert!(e.starts_with("matrix: "), "{e}");
    assert!(err("matrix = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, nan, 0, 0, 0, 1]").contains("finite"));
}

#[test]
fn a_placement_count_above_the_limit_is_refused_before_it_is_computed() {
    let d = InstanceDoc {
        translations: Some(vec![[0.0; 3]; MAX_INSTANCE_OBJECTS + 1]),
        ..doc("")
    };
    let e = placement_count(&d).unwrap_err();
    assert!(
        e.contains("1000001 entries") && e.contains("at most 1000000"),
        "{e}"
    );
}
