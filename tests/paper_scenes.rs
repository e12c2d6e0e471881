//! The paper's own scenes (read at run time from `../shared/paper-scenes`, never copied here):
//! all 15 load, and every (accelerator x traversal) renders each to exactly the bits that
//! brute force renders. CI sets `LUMIS_REQUIRE_PAPER_SCENES=1` so a missing folder fails there.

use lumis::accel::{Accel, AccelKind, BuildOptions, SegmentParams, Traversal};
use lumis::film::Film;
use lumis::render::{RenderOptions, render};
use lumis::scene::{Scene, load};
use std::path::PathBuf;

fn paper_scenes() -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/paper-scenes/scenes");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|d| {
            d.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|e| e == "scn"))
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    if files.is_empty() {
        assert!(
            std::env::var_os("LUMIS_REQUIRE_PAPER_SCENES").is_none(),
            "no paper scenes in {}",
            dir.display()
        );
        eprintln!("skipping: {} not found", dir.display());
    }
    files
}

fn bits(film: &Film) -> Vec<u32> {
    let rgba = film.rgba().iter().flat_map(|p| p.to_array());
    let aov = film.aov().iter().flat_map(|a| {
        [
            a.depth,
            a.normal.x,
            a.normal.y,
            a.normal.z,
            a.prim_id as f32,
            a.object_id as f32,
        ]
    });
    rgba.chain(aov).map(f32::to_bits).collect()
}

fn render_with(scene: &Scene, kind: AccelKind, traversal: Traversal) -> Film {
    let opts = BuildOptions {
        max_leaf_size: kind.default_leaf_size(),
    };
    let accel =
        Accel::build(kind, &scene.geometry().prim_bounds(), &opts).with_traversal(traversal);
    render(
        scene,
        &accel,
        &RenderOptions {
            seed: 3,
            threads: None,
            ..RenderOptions::default()
        },
    )
    .unwrap()
    .film
}

#[test]
fn all_paper_scenes_render_identically_under_every_accelerator_and_traversal() {
    let files = paper_scenes();
    if !files.is_empty() {
        assert_eq!(files.len(), 15, "the paper ships 15 scenes");
    }
    let traversals = [
        Traversal::Ordered,
        Traversal::Exhaustive,
        Traversal::Segments(SegmentParams {
            init: 2.0,
            max: 40_000.0,
        }),
        Traversal::Segments(SegmentParams {
            init: 4096.0,
            max: 40_000.0,
        }),
    ];
    for file in files {
        let mut scene = load(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let st = scene.settings_mut();
        // Small, but with depth of field and every reflection level the scene asks for.
        (st.width, st.height, st.spp, st.lens_samples) = (48, 27, 1, 2);
        let reference = bits(&render_with(&scene, AccelKind::Brute, Traversal::Ordered));
        for kind in [AccelKind::Bsp, AccelKind::Bsmp, AccelKind::Sah] {
            for t in traversals {
                let got = bits(&render_with(&scene, kind, t));
                let diff = got.iter().zip(&reference).filter(|(a, b)| a != b).count();
                assert_eq!(
                    diff,
                    0,
                    "{}: {kind:?} {t:?} differs from brute force in {diff} values",
                    file.display()
                );
            }
        }
    }
}
