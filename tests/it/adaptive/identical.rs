//! Where adaptive supersampling promises the same bits: T = 0 against the full render, and any
//! T across thread counts and crop windows.

use super::{assert_same_film, default_world, render_at};
use lumis_core::film::PixelWindow;
use lumis_core::render::{PassRequest, RenderOptions};

fn opts(threads: usize) -> RenderOptions {
    RenderOptions {
        seed: 7,
        threads: Some(threads),
        ..RenderOptions::default()
    }
}

/// T = 0 refines every pixel, and a refined pixel is the full render's: on a pinhole camera, with
/// depth of field (one and two lens rays a sample), with every pass, Cryptomatte and
/// transparent misses, and at spp 1, 2, 3 and 4 (base pass all, 2, 4 and 4 of the samples).
#[test]
fn threshold_zero_is_the_full_render_bit_for_bit() {
    let every_layer = RenderOptions {
        passes: PassRequest {
            light_paths: true,
            lights: true,
        },
        cryptomatte: Some(3),
        transparent: true,
        ..opts(2)
    };
    for (spp, pinhole, lens_samples, ropts) in [
        (3, true, 1, opts(2)),
        (2, false, 1, opts(2)),
        (3, false, 2, opts(1)),
        (4, true, 1, every_layer.clone()),
        (3, false, 1, every_layer),
        (1, true, 1, opts(2)),
    ] {
        let mut world = default_world(37, 21, spp, pinhole);
        world.settings_mut().lens_samples = lens_samples;
        let full = render_at(&mut world, None, &ropts);
        let zero = render_at(&mut world, Some(0.0), &ropts);
        let what = format!("spp {spp}, pinhole {pinhole}, lens samples {lens_samples}");
        assert_same_film(&full.film, &zero.film, &what);
        assert!(
            full.film.aov().iter().all(|a| a.samples == spp * spp),
            "{what}"
        );
        assert_eq!(zero.counts.not_traced.adaptive, 0, "{what}");
        assert_eq!(full.counts.not_traced.lens, zero.counts.not_traced.lens);
        // The base pass of every pixel is traced once and re-used, never traced again: only the
        // one-pixel border (none here: the window is the image) adds camera rays.
        assert_eq!(full.counts.camera, zero.counts.camera, "{what}");
    }
}

/// Any threshold: one thread or two, the whole image or a crop of it (whose border pixels'
/// base passes are traced but not kept), the same pixels.
#[test]
fn decisions_ignore_threads_and_crops() {
    for t in [0.02, 0.1, 0.5] {
        let mut world = default_world(45, 38, 3, false);
        let one = render_at(&mut world, Some(t), &opts(1));
        let two = render_at(&mut world, Some(t), &opts(2));
        assert_same_film(&one.film, &two.film, &format!("T {t}: threads"));
        assert_eq!(one.counts, two.counts, "T {t}");
        assert!(one.counts.not_traced.adaptive > 0, "T {t}: nothing skipped");
        // Crops cutting through tiles and touching the image's edges.
        for window in [
            PixelWindow {
                x0: 7,
                x1: 30,
                y0: 3,
                y1: 20,
            },
            PixelWindow {
                x0: 0,
                x1: 17,
                y0: 17,
                y1: 38,
            },
            PixelWindow {
                x0: 44,
                x1: 45,
                y0: 0,
                y1: 1,
            },
        ] {
            let crop = render_at(
                &mut world,
                Some(t),
                &RenderOptions {
                    window: Some(window),
                    ..opts(2)
                },
            );
            for y in window.y0..window.y1 {
                for x in window.x0..window.x1 {
                    let (cx, cy) = (x - window.x0, y - window.y0);
                    assert_eq!(
                        crop.film.pixel(cx, cy).to_array().map(f32::to_bits),
                        one.film.pixel(x, y).to_array().map(f32::to_bits),
                        "T {t}, {window:?}: pixel ({x}, {y})"
                    );
                    assert_eq!(crop.film.pixel_aov(cx, cy), one.film.pixel_aov(x, y));
                }
            }
        }
    }
}
