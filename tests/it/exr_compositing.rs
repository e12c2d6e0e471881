//! The EXR header and windows a compositor relies on: chromaticities, sample counts, depth of
//! field, partial renders, the depth of misses, and renders of part of the image stored as a
//! data window inside the full display window (each read back with the exr crate).

use std::path::Path;

use exr::meta::attribute::Chromaticities;
use exr::prelude::{AttributeValue, Text, Vec2};
use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::camera::{Camera, Lens};
use lumis_core::film::PixelWindow;
use lumis_core::render::{CancelFlag, RenderOptions, Rendered, render};
use lumis_core::scene::World;
use lumis_io::output::{
    ATTR_LENS_RADIUS, ATTR_LENS_SAMPLES, ATTR_PARTIAL, ATTR_SPP, ATTR_SPP_PER_AXIS, ExrCamera,
    ExrMetadata, write_exr,
};

use crate::common;
use common::exr::{FlatImage, channel, read_exr};

fn attr(image: &FlatImage, name: &str) -> Option<AttributeValue> {
    image.layer_data[0]
        .attributes
        .other
        .get(&Text::from(name))
        .cloned()
}

/// The built-in default scene (spheres, a mesh, a ground, background visible at the top) at
/// `w x h`, one sample per pixel.
fn world(w: u32, h: u32) -> World {
    let mut scene = lumis_io::formats::default_scene().unwrap();
    let st = scene.settings_mut();
    (st.width, st.height, st.spp) = (w, h, 1);
    World::build(scene, AccelKind::Sah, &BuildOptions::default())
}

fn render_window(world: &World, window: Option<PixelWindow>) -> Rendered {
    let opts = RenderOptions {
        threads: Some(2),
        window,
        ..RenderOptions::default()
    };
    render(world, &opts).unwrap()
}

fn write(dir: &Path, r: &Rendered, camera: &Camera, meta: &ExrMetadata) -> FlatImage {
    let path = dir.join("out.exr");
    let meta = ExrMetadata {
        float_rgba: true,
        ..meta.clone()
    };
    let (full_width, full_height) = r.film.full_size();
    let camera = ExrCamera::new(camera, full_width, full_height);
    write_exr(&path, &r.film, &camera, &meta).unwrap();
    read_exr(&path)
}

#[test]
fn a_window_renders_exactly_those_pixels_of_the_full_image() {
    let w = world(45, 30);
    let full = render_window(&w, None);
    // Off the 16-pixel tile grid on every side.
    let window = PixelWindow {
        x0: 7,
        x1: 38,
        y0: 3,
        y1: 21,
    };
    let part = render_window(&w, Some(window));
    assert_eq!((part.film.width(), part.film.height()), (31, 18));
    assert_eq!(part.film.origin(), (7, 3));
    assert_eq!(part.film.full_size(), (45, 30));
    for y in 0..18 {
        for x in 0..31 {
            let (a, b) = (part.film.pixel(x, y), full.film.pixel(x + 7, y + 3));
            assert_eq!(
                a.to_array().map(f32::to_bits),
                b.to_array().map(f32::to_bits)
            );
            assert_eq!(part.film.pixel_aov(x, y), full.film.pixel_aov(x + 7, y + 3));
        }
    }

    let dir = tempfile::tempdir().unwrap();
    let image = write(
        dir.path(),
        &part,
        w.scene().camera(),
        &ExrMetadata::default(),
    );
    let layer = &image.layer_data[0];
    assert_eq!(layer.size, Vec2(31, 18));
    assert_eq!(
        layer.attributes.layer_position,
        Vec2(7, 3),
        "data window origin"
    );
    assert_eq!(image.attributes.display_window.size, Vec2(45, 30));
    assert_eq!(image.attributes.display_window.position, Vec2(0, 0));
    let r = channel(&image, "R");
    assert_eq!(r[0].to_bits(), full.film.pixel(7, 3).x.to_bits());
    // The camera matrices are the full image's, so positions project to the same pixels.
    let full_image = write(
        dir.path(),
        &full,
        w.scene().camera(),
        &ExrMetadata::default(),
    );
    assert_eq!(
        layer.attributes.world_to_normalized_device,
        full_image.layer_data[0]
            .attributes
            .world_to_normalized_device
    );
}

#[test]
fn a_window_outside_the_image_is_refused() {
    let w = world(20, 10);
    let opts = RenderOptions {
        window: Some(PixelWindow {
            x0: 5,
            x1: 25,
            y0: 0,
            y1: 10,
        }),
        ..RenderOptions::default()
    };
    let e = render(&w, &opts).unwrap_err().to_string();
    assert!(e.contains("outside the 20x10 image"), "{e}");
}

#[test]
fn header_has_chromaticities_and_sample_counts() {
    let w = world(8, 6);
    let r = render_window(&w, None);
    let dir = tempfile::tempdir().unwrap();
    let meta = ExrMetadata {
        spp_per_axis: 3,
        ..ExrMetadata::default()
    };
    let pinhole = w.scene().camera().clone().with_lens(Lens::Pinhole);
    let image = write(dir.path(), &r, &pinhole, &meta);
    let c: Chromaticities = image.attributes.chromaticities.expect("chromaticities");
    assert_eq!(
        (c.red, c.green, c.blue),
        (Vec2(0.64, 0.33), Vec2(0.30, 0.60), Vec2(0.15, 0.06))
    );
    assert_eq!(c.white, Vec2(0.3127, 0.3290), "D65");
    assert_eq!(attr(&image, ATTR_SPP), Some(AttributeValue::I32(9)));
    assert_eq!(
        attr(&image, ATTR_SPP_PER_AXIS),
        Some(AttributeValue::I32(3))
    );
    // A pinhole camera: no lens attributes, and a complete render is not partial.
    let layer = &image.layer_data[0].attributes;
    assert_eq!(layer.focus, None);
    assert_eq!(attr(&image, ATTR_LENS_RADIUS), None);
    assert_eq!(attr(&image, ATTR_LENS_SAMPLES), None);
    assert_eq!(attr(&image, ATTR_PARTIAL), None);
}

#[test]
fn depth_of_field_is_in_the_header() {
    let w = world(8, 6);
    let r = render_window(&w, None);
    let camera = w.scene().camera().clone().with_lens(Lens::Disk(0.25));
    let dir = tempfile::tempdir().unwrap();
    let meta = ExrMetadata {
        lens_samples: 5,
        ..ExrMetadata::default()
    };
    let image = write(dir.path(), &r, &camera, &meta);
    let focus = image.layer_data[0].attributes.focus.expect("focus");
    assert_eq!(focus, camera.focus_distance());
    assert_eq!(
        attr(&image, ATTR_LENS_RADIUS),
        Some(AttributeValue::F32(0.25))
    );
    assert_eq!(
        attr(&image, ATTR_LENS_SAMPLES),
        Some(AttributeValue::I32(5))
    );
}

#[test]
fn misses_get_the_chosen_depth() {
    let w = world(24, 16);
    let r = render_window(&w, None);
    let misses: Vec<usize> = (0..r.film.aov().len())
        .filter(|&i| r.film.aov()[i].object_id < 0)
        .collect();
    assert!(!misses.is_empty(), "the default scene shows background");
    let dir = tempfile::tempdir().unwrap();
    for z_miss in [f32::INFINITY, 1e10] {
        let meta = ExrMetadata {
            z_miss,
            ..ExrMetadata::default()
        };
        let z = channel(&write(dir.path(), &r, w.scene().camera(), &meta), "Z");
        for (i, a) in r.film.aov().iter().enumerate() {
            let want = if a.object_id < 0 { z_miss } else { a.depth };
            assert_eq!(z[i].to_bits(), want.to_bits(), "pixel {i}");
        }
    }
}

#[test]
fn a_cancelled_render_keeps_no_tile_and_says_partial() {
    let w = world(40, 20);
    let cancel = CancelFlag::default();
    cancel.raise();
    let opts = RenderOptions {
        cancel,
        ..RenderOptions::default()
    };
    let r = render(&w, &opts).unwrap();
    assert!(r.is_partial());
    assert_eq!((r.unfinished_tiles, r.tiles), (6, 6));
    assert!(r.film.rgba().iter().all(|p| p.w == 0.0 && p.x == 0.0));
    let dir = tempfile::tempdir().unwrap();
    let meta = ExrMetadata {
        partial: true,
        ..ExrMetadata::default()
    };
    let image = write(dir.path(), &r, w.scene().camera(), &meta);
    assert_eq!(attr(&image, ATTR_PARTIAL), Some(AttributeValue::I32(1)));
    assert!(channel(&image, "A").iter().all(|&a| a == 0.0));
}
