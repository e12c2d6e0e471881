//! The files `lumis-lab load` generates are valid: both formats load with the same triangle
//! count and bounds, so the benchmark times real loads.

use super::files::{write_glb, write_obj};

#[test]
fn generated_obj_and_glb_load_with_the_same_geometry() {
    let dir = tempfile::tempdir().unwrap();
    let (obj, glb) = (dir.path().join("g.obj"), dir.path().join("g.glb"));
    write_obj(&obj, 20).unwrap();
    write_glb(&glb, 20).unwrap();
    let a = lumis_io::formats::load(&obj).unwrap();
    let b = lumis_io::formats::load(&glb).unwrap();
    let tris = |s: &lumis_core::scene::Scene| {
        s.geometry()
            .meshes()
            .iter()
            .map(|m| m.triangle_count())
            .sum::<usize>()
    };
    assert_eq!((tris(&a), tris(&b)), (800, 800));
    let (ba, bb) = (a.geometry().bounds(), b.geometry().bounds());
    assert!(
        (ba.min - bb.min).abs().max_element() < 1e-6
            && (ba.max - bb.max).abs().max_element() < 1e-6,
        "{ba:?} vs {bb:?}"
    );
}
