//! The paper's own scenes (read at run time from `../shared/paper-scenes`, never copied here):
//! all 15 load with the original's defaults for what they leave out, and every (accelerator x
//! traversal) renders each to exactly the bits that brute force renders. CI sets
//! `LUMIS_REQUIRE_PAPER_SCENES=1` so a missing folder fails there.

use crate::common;

use common::files::paper_scenes;
use lumis_core::accel::{AccelKind, BuildOptions, SegmentParams, Traversal};
use lumis_core::camera::Lens;
use lumis_core::film::Film;
use lumis_core::render::{RenderOptions, render};
use lumis_core::scene::{Scene, World};
use lumis_io::formats::load;

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
        ..Default::default()
    };
    let world = World::build(scene.clone(), kind, &opts).with_traversal(traversal);
    render(
        &world,
        &RenderOptions {
            seed: 3,
            threads: None,
            ..RenderOptions::default()
        },
    )
    .unwrap()
    .film
}

/// The last value a scene file gives `keyword` (the last statement wins), read here without
/// lumis's parser: tokens up to a `#` on each line.
fn last_value(text: &str, keyword: &str) -> Option<f32> {
    let tokens: Vec<&str> = text
        .lines()
        .flat_map(|l| l.split_whitespace().take_while(|t| !t.starts_with('#')))
        .collect();
    tokens
        .windows(2)
        .filter(|w| w[0] == keyword)
        .filter_map(|w| w[1].parse().ok())
        .next_back()
}

#[test]
fn paper_scenes_take_the_originals_defaults() {
    let mut with_dof = 0;
    for file in paper_scenes() {
        let text = std::fs::read_to_string(&file).unwrap();
        let scene = load(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let st = scene.settings();
        // Without the statement the original recurses 10 times and jitters the lens by 5.
        let depth = last_value(&text, "maxReflections").unwrap_or(10.0);
        assert_eq!(st.max_depth as f32, depth, "{}", file.display());
        let lens = match last_value(&text, "dispersion").unwrap_or(5.0) {
            d if d > 0.0 => Lens::Square(d),
            _ => Lens::Pinhole,
        };
        assert_eq!(scene.camera().lens(), lens, "{}", file.display());
        assert_eq!(st.lens_samples, 5, "{}", file.display());
        with_dof += scene.camera().has_depth_of_field() as usize;
    }
    // Only ballsOnAPlaneClose (dispersion 0) is a pinhole among the 15.
    if with_dof > 0 {
        assert_eq!(with_dof, 14);
    }
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
