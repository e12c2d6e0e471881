//! §1, level by level: a scene built to exercise one decision traces none of the rays that
//! decision skips, and its image is the `--effects all` image bit for bit.

use super::{auto_and_all, render_mode};
use lumis_core::camera::Camera;
use lumis_core::effects::EffectMode;
use lumis_core::geometry::{Mesh, Sphere};
use lumis_core::light::Light;
use lumis_core::material::{Material, Texture};
use lumis_core::math::Vec3;
use lumis_core::render::{RenderOptions, render};
use lumis_core::scene::{Scene, SceneBuilder, World};

const W: u32 = 24;
const H: u32 = 16;

/// A ground square at y = 0 (normal +y) of material `ground`, a sphere of material `ball`
/// resting on it, the given lights, seen from above at an angle.
fn stage(ground: Material, ball: Material, lights: Vec<Light>) -> SceneBuilder {
    let mut b = SceneBuilder::new();
    let g = b.add_material(ground);
    let m = b.add_material(ball);
    let s = 4.0;
    let quad = Mesh::new(
        vec![
            Vec3::new(-s, 0.0, -s),
            Vec3::new(s, 0.0, -s),
            Vec3::new(s, 0.0, s),
            Vec3::new(-s, 0.0, s),
        ],
        None,
        None,
        vec![[0, 2, 1], [0, 3, 2]],
    )
    .expect("valid quad");
    b.add_mesh("ground", quad, g);
    b.add_sphere(
        "ball",
        Sphere {
            center: Vec3::new(0.0, 1.0, 0.0),
            radius: 1.0,
        },
        m,
    );
    for l in lights {
        b.add_light(l);
    }
    let st = b.settings_mut();
    (st.width, st.height, st.spp) = (W, H, 1);
    b
}

fn camera() -> Camera {
    Camera::look_at(
        Vec3::new(0.0, 5.0, 6.0),
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::Y,
        50.0,
        0.0,
        None,
    )
    .expect("camera")
}

fn build(b: SceneBuilder) -> Scene {
    b.build(camera()).expect("scene within the value limits")
}

fn matte(c: f32) -> Material {
    Material {
        diffuse: Texture::Solid(Vec3::splat(c)),
        ..Material::default()
    }
}

fn point(position: Vec3, power: f32) -> Light {
    Light::Point {
        position,
        intensity: Vec3::splat(power),
    }
}

#[test]
fn no_shadow_ray_to_a_light_behind_every_surface() {
    // Below the ground: it faces away from the light, and the ball's lit underside is hidden
    // from the camera by the ground (the camera never sees it).
    let mut scene = build(stage(
        matte(0.5),
        matte(0.5),
        vec![point(Vec3::new(0.0, -3.0, 0.0), 50.0)],
    ));
    let (auto, all) = auto_and_all("light below", &mut scene);
    let skips = auto.counts.not_traced.shadow;
    assert!(skips.back_facing > 0);
    // Only the ball's lower sides can see the light (through the ground, which blocks it).
    assert!(skips.back_facing > auto.counts.shadow);
    assert!(auto.counts.shadow < all.counts.shadow);
}

#[test]
fn no_shadow_ray_outside_a_spot_cone() {
    // A narrow spot above the ball, pointing straight up: nothing lies in its cone.
    let spot = Light::Spot {
        position: Vec3::new(0.0, 4.0, 0.0),
        direction: Vec3::Y,
        intensity: Vec3::splat(80.0),
        cos_inner: 0.95,
        cos_outer: 0.9,
    };
    let mut scene = build(stage(matte(0.5), matte(0.5), vec![spot]));
    let (auto, all) = auto_and_all("spot away", &mut scene);
    assert_eq!(auto.counts.shadow, 0);
    assert!(auto.counts.not_traced.shadow.outside_cone > 0);
    assert!(all.counts.shadow > 0);
}

#[test]
fn no_shadow_ray_to_a_zero_intensity_light() {
    let lights = vec![
        point(Vec3::new(2.0, 5.0, 2.0), 0.0),
        point(Vec3::new(-2.0, 5.0, 2.0), 40.0),
    ];
    let mut scene = build(stage(matte(0.5), matte(0.5), lights));
    let (auto, all) = auto_and_all("dark light", &mut scene);
    let skips = auto.counts.not_traced.shadow;
    assert!(skips.dark_light > 0);
    assert_eq!(auto.analysis.lights_reachable, vec![false, true]);
    assert!(auto.analysis.shadows.reason.contains("1 of 2 lights"));
    // Exactly one shadow ray per reachable light per shading point, at most.
    assert!(auto.counts.shadow <= all.counts.shadow / 2);
}

#[test]
fn no_shadow_ray_from_a_material_that_ignores_light() {
    let black = Material {
        diffuse: Texture::Solid(Vec3::ZERO),
        emission: Vec3::new(0.3, 0.2, 0.1),
        ..Material::default()
    };
    let mut scene = build(stage(
        black.clone(),
        black,
        vec![point(Vec3::Y * 5.0, 50.0)],
    ));
    let (auto, all) = auto_and_all("emitters only", &mut scene);
    assert_eq!(auto.counts.shadow, 0);
    assert!(auto.counts.not_traced.shadow.material_unlit > 0);
    assert!(!auto.analysis.shadows.on, "{:?}", auto.analysis.shadows);
    assert!(all.counts.shadow > 0);
}

#[test]
fn no_reflection_or_refraction_rays_without_such_materials() {
    let mut scene = build(stage(
        matte(0.5),
        matte(0.7),
        vec![point(Vec3::Y * 5.0, 50.0)],
    ));
    let (auto, all) = auto_and_all("matte", &mut scene);
    assert_eq!((auto.counts.reflection, auto.counts.refraction), (0, 0));
    assert!(!auto.analysis.reflection.on && !auto.analysis.refraction.on);
    assert_eq!(auto.analysis.refraction.reason, "no material transmits");
    assert!(all.counts.reflection > 0 && all.counts.refraction > 0);
}

#[test]
fn no_refraction_ray_under_total_internal_reflection() {
    // The camera sits in glass (medium index 1.5) and looks at a bubble of air: rays meeting
    // the bubble beyond the critical angle cannot leave the glass.
    let air = Material {
        diffuse: Texture::Solid(Vec3::ZERO),
        transmission: 1.0,
        ior: 1.0,
        ..Material::default()
    };
    let mut b = stage(matte(0.5), air, vec![point(Vec3::Y * 5.0, 50.0)]);
    b.settings_mut().medium_ior = 1.5;
    let mut scene = build(b);
    let (auto, _) = auto_and_all("bubble", &mut scene);
    assert!(auto.counts.not_traced.refraction.zero_weight > 0);
    assert!(auto.counts.refraction > 0);
}

#[test]
fn a_pinhole_camera_traces_one_lens_ray_per_sample() {
    let mut b = stage(matte(0.5), matte(0.5), vec![point(Vec3::Y * 5.0, 50.0)]);
    b.settings_mut().lens_samples = 4;
    let scene = build(b);
    let r = render_mode(&scene, EffectMode::Auto);
    let samples = u64::from(W * H);
    assert_eq!(r.counts.camera, samples);
    assert_eq!(r.counts.not_traced.lens, 3 * samples);
    assert!(!r.analysis.depth_of_field.on);
    assert!(r.analysis.depth_of_field.reason.contains("the 4 lens rays"));
}

#[test]
fn aov_rays_only_when_the_output_has_aov_layers() {
    let scene = build(stage(
        matte(0.5),
        matte(0.5),
        vec![point(Vec3::Y * 5.0, 50.0)],
    ));
    let world = World::build(
        scene.clone(),
        lumis_core::accel::AccelKind::Sah,
        &lumis_core::accel::BuildOptions::default(),
    );
    let png_only = RenderOptions {
        aov_layers: false,
        ..RenderOptions::default()
    };
    let without = render(&world, &png_only).expect("render");
    let with = render(&world, &RenderOptions::default()).expect("render");
    let pixels = u64::from(W * H);
    assert_eq!(
        (without.counts.aov, without.counts.not_traced.aov),
        (0, pixels)
    );
    assert_eq!((with.counts.aov, with.counts.not_traced.aov), (pixels, 0));
    assert_eq!(without.film.rgba(), with.film.rgba());
    assert!(without.film.aov().iter().all(|a| a.object_id == -1));
    // The reference traces them even for a PNG.
    let all = render(
        &world,
        &RenderOptions {
            effects: EffectMode::All,
            ..png_only
        },
    )
    .expect("render");
    assert_eq!(all.counts.aov, pixels);
}
