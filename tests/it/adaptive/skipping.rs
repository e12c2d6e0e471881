//! What adaptive supersampling skips and what it keeps: flat regions take the base pass,
//! silhouettes every sample; a refined pixel is the full render's; alpha, Cryptomatte coverage
//! and the passes are normalised by the samples taken, and the counts add up.

use super::{default_world, render_at};
use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::film::Film;
use lumis_core::render::{PassRequest, RenderOptions, Rendered};
use lumis_core::scene::World;

/// A sphere of one flat colour (ambient light only, no lamp) on black: every sample on it has
/// the same value, every sample off it is RGBA 0.
const FLAT_SPHERE: &str = r#"
[render]
width = 48
height = 40
spp = 4
ambient = [1.0, 1.0, 1.0]
background = [0.0, 0.0, 0.0]

[camera]
position = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
fov = 40.0

[materials.flat]
diffuse = [0.5, 0.25, 0.125]

[[sphere]]
name = "ball"
center = [0.0, 0.0, 0.0]
radius = 1.2
material = "flat"
"#;

fn flat_sphere() -> World {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("flat.toml");
    std::fs::write(&path, FLAT_SPHERE).unwrap();
    let scene = lumis_io::formats::load(&path).unwrap();
    World::build(scene, AccelKind::Sah, &BuildOptions::default())
}

fn opts() -> RenderOptions {
    RenderOptions {
        seed: 3,
        threads: Some(2),
        cryptomatte: Some(2),
        ..RenderOptions::default()
    }
}

/// Whether the centre rays of the 5x5 pixels around `(x, y)` (those inside the image) all hit
/// the same object or all miss: then the pixel and its 8 neighbours lie wholly on one side of
/// the sphere's convex silhouette, and so do all their samples.
fn far_from_silhouette(film: &Film, x: u32, y: u32) -> bool {
    let id = film.pixel_aov(x, y).object_id;
    (-2..=2).all(|dy: i32| {
        (-2..=2).all(|dx: i32| {
            let (nx, ny) = (x as i32 + dx, y as i32 + dy);
            nx < 0
                || ny < 0
                || nx >= film.width() as i32
                || ny >= film.height() as i32
                || film.pixel_aov(nx as u32, ny as u32).object_id == id
        })
    })
}

#[test]
fn flat_regions_keep_the_base_pass_and_silhouettes_take_every_sample() {
    let mut world = flat_sphere();
    let r = render_at(&mut world, Some(0.05), &opts());
    let film = &r.film;
    let (mut kept, mut refined) = (0, 0);
    for y in 0..film.height() {
        for x in 0..film.width() {
            let samples = film.pixel_aov(x, y).samples;
            let alpha = film.pixel(x, y).w;
            assert!(samples == 4 || samples == 16, "({x}, {y}): {samples}");
            if far_from_silhouette(film, x, y) {
                assert_eq!(samples, 4, "({x}, {y}) is inside a flat region");
            }
            // Partly covered by the samples it took: its base samples disagreed in alpha.
            if alpha != 0.0 && alpha != 1.0 {
                assert_eq!(samples, 16, "({x}, {y}): alpha {alpha} from the base pass");
            }
            if samples == 4 {
                kept += 1;
            } else {
                refined += 1;
                assert!(!far_from_silhouette(film, x, y));
            }
        }
    }
    // The silhouette of a sphere ~20 pixels across crosses a few dozen pixels.
    assert!(
        refined >= 40 && kept >= 1500,
        "{refined} refined, {kept} kept"
    );
    assert_eq!(r.counts.not_traced.adaptive, 12 * kept);
    // Coverage is counted over the samples taken: the one object covers what alpha covers.
    let crypto = &film.crypto()[0];
    for (i, p) in film.rgba().iter().enumerate() {
        let coverage: f32 = crypto.pixel(i).iter().map(|r| r.coverage).sum();
        assert_eq!(coverage, p.w, "pixel {i}");
    }
}

/// A pixel that took every sample is the full render's, bit for bit; only pixels that kept
/// their base pass may differ, and a higher threshold keeps more of them.
#[test]
fn only_pixels_on_the_base_pass_differ_from_the_full_render() {
    let mut world = default_world(64, 36, 3, false);
    let full = render_at(&mut world, None, &opts());
    let mut last_kept = 0;
    for t in [0.02, 0.1, 0.3] {
        let r = render_at(&mut world, Some(t), &opts());
        let (mut kept, mut differ) = (0, 0);
        for (i, (a, b)) in r.film.rgba().iter().zip(full.film.rgba()).enumerate() {
            let same = a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits);
            match r.film.aov()[i].samples {
                9 => assert!(same, "T {t}: refined pixel {i} differs"),
                4 => kept += 1,
                n => panic!("T {t}: pixel {i} took {n} samples"),
            }
            differ += usize::from(!same);
        }
        assert!(differ <= kept && kept > last_kept, "T {t}: {kept} kept");
        last_kept = kept;
        assert_eq!(r.counts.not_traced.adaptive, 5 * kept as u64, "T {t}");
    }
}

/// The light-path passes still add up to the beauty where a pixel kept its base pass, and the
/// depth-of-field lens rays are counted per sample taken.
#[test]
fn passes_add_up_and_counts_follow_the_samples_taken() {
    let mut world = default_world(40, 24, 3, false);
    world.settings_mut().lens_samples = 2;
    let ropts = RenderOptions {
        passes: PassRequest {
            light_paths: true,
            lights: false,
        },
        ..opts()
    };
    let r: Rendered = render_at(&mut world, Some(0.1), &ropts);
    let film = &r.film;
    let kept = film.aov().iter().filter(|a| a.samples == 4).count();
    assert!(kept > 0);
    for (i, p) in film.rgba().iter().enumerate() {
        let sum = film
            .passes()
            .iter()
            .filter(|l| l.name() != "shadow")
            .fold(lumis_core::math::Vec3::ZERO, |s, l| s + l.values()[i]);
        let beauty = p.truncate();
        assert!(
            (sum - beauty).abs().max_element() <= 1e-5 + 1e-5 * beauty.max_element(),
            "pixel {i}: passes {sum} against {beauty}"
        );
    }
    let skipped: u64 = film.aov().iter().map(|a| u64::from(9 - a.samples)).sum();
    assert_eq!(r.counts.not_traced.adaptive, 2 * skipped);
}
