//! Nested glass near and far from the origin. Oracle: energy conservation. With a white
//! background, no lights and no absorption, every split of a path into Fresnel-reflected and
//! refracted parts keeps the weights summing to 1, so every pixel is 1 minus the weight lost at
//! the depth cap — never more than 1 — and the scene 1e5 from the origin must give the same
//! image as at the origin (a ray that re-hits the surface it leaves takes extra bounces and
//! loses weight at the cap; one that skips a surface takes another path).

use super::harness::render_everywhere;
use lumis_core::camera::Camera;
use lumis_core::geometry::Sphere;
use lumis_core::material::{Material, Texture};
use lumis_core::math::Vec3;
use lumis_core::scene::SceneBuilder;

fn nested_glass_at(offset: Vec3) -> Vec<f32> {
    let mut b = SceneBuilder::new();
    let s = b.settings_mut();
    (s.width, s.height, s.spp, s.max_depth) = (48, 48, 1, 12);
    (s.ambient, s.background) = (Vec3::ZERO, Vec3::ONE);
    // Every branch traced: a cutoff drops weight, and drops it differently near and far.
    s.cutoff = 0.0;
    let glass = |ior| Material {
        diffuse: Texture::Solid(Vec3::ZERO),
        transmission: 1.0,
        ior,
        ..Material::default()
    };
    let (outer, inner) = (b.add_material(glass(1.5)), b.add_material(glass(1.33)));
    b.add_sphere(
        "outer",
        Sphere {
            center: offset,
            radius: 1.0,
        },
        outer,
    );
    b.add_sphere(
        "inner",
        Sphere {
            center: offset + Vec3::new(0.1, -0.05, 0.0),
            radius: 0.55,
        },
        inner,
    );
    b.add_sphere(
        "core",
        Sphere {
            center: offset + Vec3::new(0.1, -0.05, 0.1),
            radius: 0.2,
        },
        outer,
    );
    let cam = Camera::look_at(
        offset + Vec3::new(0.3, 0.4, 3.2),
        offset,
        Vec3::Y,
        40.0,
        0.0,
        None,
    )
    .unwrap();
    let scene = b.build(cam).expect("scene within the value limits");
    let film = render_everywhere(&scene);
    film.rgba().iter().map(|p| p.x).collect()
}

#[test]
fn nested_glass_conserves_energy_near_and_far_from_the_origin() {
    let near = nested_glass_at(Vec3::ZERO);
    let far = nested_glass_at(Vec3::new(1e5, -1e5, 1e5));
    for (what, img) in [("near", &near), ("far", &far)] {
        let max = img.iter().cloned().fold(0.0, f32::max);
        let min = img.iter().cloned().fold(1.0, f32::min);
        assert!(max <= 1.0 + 1e-4, "{what}: a pixel gains energy: {max}");
        assert!(
            min >= 0.9,
            "{what}: a pixel lost {} of its weight",
            1.0 - min
        );
    }
    let diff = near
        .iter()
        .zip(&far)
        .map(|(a, b)| (a - b).abs())
        .sum::<f32>()
        / near.len() as f32;
    assert!(diff < 2e-3, "far image differs by {diff} on average");
}
