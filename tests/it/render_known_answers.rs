//! Renders into memory with analytic expectations: Lambert under a point light, a mirror, a
//! glass slab at normal incidence, a shadowed pixel, effect gating, thread-count invariance.

use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::camera::Camera;
use lumis_core::film::Film;
use lumis_core::geometry::{Mesh, Sphere};
use lumis_core::integrator::RayCounts;
use lumis_core::light::Light;
use lumis_core::material::{Material, Texture};
use lumis_core::math::{Vec2, Vec3, Vec4};
use lumis_core::render::{RenderOptions, render};
use lumis_core::scene::{Scene, SceneBuilder, World};
use std::f32::consts::PI;

fn quad(center: Vec3, u: Vec3, v: Vec3) -> Mesh {
    let p = vec![
        center - u - v,
        center + u - v,
        center + u + v,
        center - u + v,
    ];
    Mesh::new(p, None, None, vec![[0, 1, 2], [0, 2, 3]]).unwrap()
}

fn matte(kd: f32) -> Material {
    Material {
        diffuse: Texture::Solid(Vec3::splat(kd)),
        ..Material::default()
    }
}

fn emitter(e: Vec3) -> Material {
    Material {
        diffuse: Texture::Solid(Vec3::ZERO),
        emission: e,
        ..Material::default()
    }
}

fn builder(w: u32, h: u32, spp: u32) -> SceneBuilder {
    let mut b = SceneBuilder::new();
    let s = b.settings_mut();
    (s.width, s.height, s.spp, s.ambient, s.max_depth) = (w, h, spp, Vec3::ZERO, 5);
    b
}

fn run(scene: &Scene, threads: usize) -> (Film, RayCounts) {
    let world = World::build(scene.clone(), AccelKind::Sah, &BuildOptions::default());
    let r = render(
        &world,
        &RenderOptions {
            seed: 7,
            threads: Some(threads),
            ..RenderOptions::default()
        },
    )
    .unwrap();
    (r.film, r.counts)
}

/// The pixel a world point projects to, through the camera's worldToNDC.
fn pixel_of(scene: &Scene, p: Vec3) -> (u32, u32) {
    let st = scene.settings();
    let q = scene.camera().world_to_ndc(st.width, st.height) * p.extend(1.0);
    (
        (q.x / q.w * st.width as f32) as u32,
        (q.y / q.w * st.height as f32) as u32,
    )
}

#[test]
fn lambertian_sphere_under_point_light_matches_analytic_radiance() {
    // Unit sphere, kd = 0.5, light of intensity I on the +z axis at distance 5 from the centre.
    let intensity = 16.0 * PI;
    let mut b = builder(101, 101, 2);
    let m = b.add_material(matte(0.5));
    b.add_sphere(
        "ball",
        Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        },
        m,
    );
    b.add_light(Light::Point {
        position: Vec3::new(0.0, 0.0, 5.0),
        intensity: Vec3::splat(intensity),
    });
    let cam = Camera::look_at(
        Vec3::new(0.0, 0.0, 10.0),
        Vec3::ZERO,
        Vec3::Y,
        14.0,
        0.0,
        None,
    )
    .unwrap();
    let scene = b.build(cam).expect("scene within the value limits");
    let (film, counts) = run(&scene, 2);
    // Expected L = kd/pi * I cos / d^2 at the point each pixel-centre ray hits; samples jitter
    // within the pixel, so the tolerance is 1% of the value.
    let light = Vec3::new(0.0, 0.0, 5.0);
    let mut checked = 0;
    for (x, y) in [(50, 50), (60, 45), (40, 62), (70, 70), (30, 55)] {
        let aov = film.pixel_aov(x, y);
        assert_eq!(aov.prim_id, 0, "pixel ({x},{y}) should see the sphere");
        let dir = scene
            .camera()
            .pinhole_dir(Vec2::new(x as f32 + 0.5, y as f32 + 0.5), 101, 101);
        let p = scene.camera().position() + dir * (aov.depth / dir.dot(scene.camera().forward()));
        let to_light = light - p;
        let cos = p.normalize().dot(to_light.normalize());
        let expected = 0.5 / PI * intensity * cos / to_light.length_squared();
        let got = film.pixel(x, y);
        assert!(
            (got.x - expected).abs() <= 0.01 * expected,
            "pixel ({x},{y}): {} vs {expected}",
            got.x
        );
        assert_eq!(got.w, 1.0);
        checked += 1;
    }
    assert_eq!(checked, 5);
    assert!(
        (film.pixel(50, 50).x - 0.5).abs() < 0.005,
        "centre radiance {}",
        film.pixel(50, 50).x
    );
    // Corner pixels miss: transparent black.
    assert_eq!(film.pixel(0, 0), Vec4::ZERO);
    // Nothing reflects or refracts, so no such rays were traced.
    assert_eq!((counts.reflection, counts.refraction), (0, 0));
    assert!(counts.shadow > 0);
}

#[test]
fn mirror_reflects_the_known_colour() {
    // A mirror quad facing the camera reflects the emissive inside of a surrounding sphere.
    let mut b = builder(32, 32, 1);
    let sky = Vec3::new(0.2, 0.4, 0.6);
    let e = b.add_material(emitter(sky));
    let mirror = b.add_material(Material {
        diffuse: Texture::Solid(Vec3::ZERO),
        reflectivity: 0.8,
        ..Material::default()
    });
    b.add_sphere(
        "dome",
        Sphere {
            center: Vec3::ZERO,
            radius: 100.0,
        },
        e,
    );
    b.add_mesh(
        "mirror",
        quad(Vec3::ZERO, Vec3::X * 2.0, Vec3::Y * 2.0),
        mirror,
    );
    let cam = Camera::look_at(
        Vec3::new(0.3, 0.2, 5.0),
        Vec3::ZERO,
        Vec3::Y,
        10.0,
        0.0,
        None,
    )
    .unwrap();
    let scene = b.build(cam).expect("scene within the value limits");
    let (film, counts) = run(&scene, 2);
    let expected = sky * 0.8;
    for y in 0..32 {
        for x in 0..32 {
            let got = film.pixel(x, y).truncate();
            assert!(
                (got - expected).abs().max_element() < 1e-6,
                "pixel ({x},{y}) {got} vs {expected}"
            );
        }
    }
    assert_eq!(counts.reflection, 32 * 32);
    assert_eq!(
        (counts.shadow, counts.refraction),
        (0, 0),
        "no lights, no glass: no such rays"
    );
}

#[test]
fn glass_slab_at_normal_incidence_transmits_the_fresnel_fraction() {
    // Slab 1 thick, n = 1.5, in front of an emitter of radiance 1. At normal incidence F = 0.04;
    // with max_depth 5 the paths reaching the emitter are the direct one and one internal
    // round trip: T = (1 - F)^2 (1 + F^2). The round trip weighs F^2 (1 - F)^2 < 0.01, so the
    // default contribution cutoff is turned off: the analytic answer counts every branch.
    let mut b = builder(9, 9, 1);
    b.settings_mut().cutoff = 0.0;
    let glass = b.add_material(Material {
        diffuse: Texture::Solid(Vec3::ZERO),
        transmission: 1.0,
        ior: 1.5,
        ..Material::default()
    });
    let e = b.add_material(emitter(Vec3::ONE));
    b.add_mesh(
        "slab",
        box_mesh(Vec3::new(-3.0, -3.0, -0.5), Vec3::new(3.0, 3.0, 0.5)),
        glass,
    );
    b.add_mesh(
        "wall",
        quad(Vec3::new(0.0, 0.0, -3.0), Vec3::X * 50.0, Vec3::Y * 50.0),
        e,
    );
    let cam = Camera::look_at(
        Vec3::new(0.0, 0.0, 10.0),
        Vec3::ZERO,
        Vec3::Y,
        0.5,
        0.0,
        None,
    )
    .unwrap();
    let scene = b.build(cam).expect("scene within the value limits");
    let (film, counts) = run(&scene, 1);
    let f = 0.04f32;
    let expected = (1.0 - f) * (1.0 - f) * (1.0 + f * f);
    let got = film.pixel(4, 4).x;
    assert!(
        (got - expected).abs() < 1e-4,
        "transmitted {got}, expected {expected}"
    );
    assert!(counts.refraction > 0 && counts.reflection > 0);
}

#[test]
fn shadowed_pixel_is_exactly_ambient() {
    let mut b = builder(64, 48, 1);
    b.settings_mut().ambient = Vec3::new(0.1, 0.2, 0.3);
    let ground = b.add_material(matte(0.5));
    b.add_mesh(
        "ground",
        quad(Vec3::ZERO, Vec3::X * 20.0, Vec3::Z * 20.0),
        ground,
    );
    b.add_sphere(
        "blocker",
        Sphere {
            center: Vec3::new(0.0, 2.0, 0.0),
            radius: 1.0,
        },
        ground,
    );
    b.add_light(Light::Point {
        position: Vec3::new(0.0, 5.0, 0.0),
        intensity: Vec3::splat(100.0),
    });
    let cam = Camera::look_at(
        Vec3::new(0.0, 1.0, 6.0),
        Vec3::ZERO,
        Vec3::Y,
        45.0,
        0.0,
        None,
    )
    .unwrap();
    let scene = b.build(cam).expect("scene within the value limits");
    let (film, _) = run(&scene, 2);
    let (x, y) = pixel_of(&scene, Vec3::ZERO);
    assert_eq!(
        film.pixel_aov(x, y).object_id,
        0,
        "the shadowed pixel must see the ground"
    );
    let ambient = Vec3::new(0.1, 0.2, 0.3) * 0.5;
    assert_eq!(film.pixel(x, y).truncate(), ambient);
    // A lit ground point is brighter than ambient.
    let (lx, ly) = pixel_of(&scene, Vec3::new(3.0, 0.0, 2.0));
    assert!(film.pixel(lx, ly).x > ambient.x + 0.1);
}

#[test]
fn image_and_counts_do_not_depend_on_thread_count() {
    let mut b = builder(48, 40, 2);
    let m = b.add_material(Material {
        reflectivity: 0.3,
        specular: Vec3::splat(0.5),
        shininess: 20.0,
        ..matte(0.6)
    });
    let g = b.add_material(Material {
        transmission: 1.0,
        ..matte(0.0)
    });
    b.add_sphere(
        "a",
        Sphere {
            center: Vec3::new(-0.6, 0.0, 0.0),
            radius: 0.5,
        },
        m,
    );
    b.add_sphere(
        "b",
        Sphere {
            center: Vec3::new(0.6, 0.0, 0.0),
            radius: 0.5,
        },
        g,
    );
    b.add_mesh(
        "floor",
        quad(Vec3::new(0.0, -0.5, 0.0), Vec3::X * 5.0, Vec3::Z * 5.0),
        m,
    );
    b.add_light(Light::Point {
        position: Vec3::new(2.0, 4.0, 3.0),
        intensity: Vec3::splat(40.0),
    });
    let cam = Camera::look_at(
        Vec3::new(0.0, 1.0, 4.0),
        Vec3::ZERO,
        Vec3::Y,
        40.0,
        0.05,
        None,
    )
    .unwrap();
    let scene = b.build(cam).expect("scene within the value limits");
    let (f1, c1) = run(&scene, 1);
    let (f2, c2) = run(&scene, 2);
    assert_eq!(f1, f2);
    assert_eq!(c1, c2);
}

/// An axis-aligned closed box, faces wound outwards.
fn box_mesh(lo: Vec3, hi: Vec3) -> Mesh {
    let p: Vec<Vec3> = (0..8)
        .map(|i| {
            Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        })
        .collect();
    let faces = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let idx = faces
        .iter()
        .flat_map(|f| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]])
        .collect();
    Mesh::new(p, None, None, idx).unwrap()
}
