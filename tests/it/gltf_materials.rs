//! glTF materials, textures and vertex attributes, by their pixels: the assets
//! `tools/lumis_tools/gltf_material_assets.py` writes to `assets/gltf/materials/` are quads filling the
//! image of a camera on +Z, rendered with ambient 1 so that a rough dielectric pixel shows
//! emission + base colour * occlusion (their lights have intensity 0 unless said otherwise).

use crate::common;

use std::path::PathBuf;
use std::process::Command;

use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::camera::Camera;
use lumis_core::film::Film;
use lumis_core::light::Light;
use lumis_core::math::{Ray, Vec3};
use lumis_core::scene::{Scene, World};
use lumis_io::formats::{self, LoadOptions};

fn asset(name: &str) -> PathBuf {
    common::files::gltf_asset("materials").join(name)
}

fn load(name: &str) -> Scene {
    common::render::load(&asset(name))
}

/// Renders `s` `size` pixels square through `kind` from a camera on +Z whose view is exactly
/// the square [-1, 1]^2 of the plane z = 0, with ambient 1.
fn render_front(s: &mut Scene, size: u32, kind: AccelKind) -> Film {
    // tan(20 degrees) * distance = 1.
    let distance = 1.0 / 20f32.to_radians().tan();
    let cam = Camera::look_at(Vec3::Z * distance, Vec3::ZERO, Vec3::Y, 40.0, 0.0, None).unwrap();
    s.set_camera(cam);
    s.settings_mut().ambient = Vec3::ONE;
    common::render::film(s.clone(), (size, size), kind, &BuildOptions::default())
}

/// Asset `name` by [`render_front`] at 16 pixels with background `sky`, which mirrors show.
fn front_under_sky(name: &str, sky: Vec3) -> Film {
    let mut s = load(name);
    s.settings_mut().background = sky;
    render_front(&mut s, 16, AccelKind::Sah)
}

/// The irradiance of the scene's one directional light.
fn sun(s: &Scene) -> f32 {
    match s.lights() {
        [Light::Directional { irradiance, .. }] => irradiance.x,
        other => panic!("expected one directional light, got {other:?}"),
    }
}

fn rgb(film: &Film, x: u32, y: u32) -> Vec3 {
    film.pixel(x, y).truncate()
}

fn assert_rgb(film: &Film, x: u32, y: u32, want: Vec3, what: &str) {
    let got = rgb(film, x, y);
    assert!(
        (got - want).abs().max_element() < 1e-4,
        "{what}: pixel ({x}, {y}) is {got}, expected {want}"
    );
}

/// The NEAREST texel index of coordinate `t` in an image `n` texels wide, if the whole pixel
/// `[t0, t1]` lies in one texel (else `None`: the pixel straddles a texel edge).
fn texel(t0: f32, t1: f32, n: f32) -> Option<i64> {
    let (a, b) = (((t0 + 1e-3) * n).floor(), ((t1 - 1e-3) * n).floor());
    (a == b).then_some(a as i64)
}

#[test]
fn emissive_texture_multiplies_factor_and_strength() {
    let mut s = load("emissive.gltf");
    let film = render_front(&mut s, 16, AccelKind::Sah);
    // emissiveFactor (1, 0.5, 1) x strength 2 x (red, green / blue, white).
    assert_rgb(&film, 4, 4, Vec3::new(2.0, 0.0, 0.0), "red texel");
    assert_rgb(&film, 11, 4, Vec3::new(0.0, 1.0, 0.0), "green texel");
    assert_rgb(&film, 4, 11, Vec3::new(0.0, 0.0, 2.0), "blue texel");
    assert_rgb(&film, 11, 11, Vec3::new(2.0, 1.0, 2.0), "white texel");
}

#[test]
fn normal_texture_bends_shading_with_file_and_generated_tangents() {
    // Texels in tangent space (tangent +x, bitangent +y, up the image): tipped to +x, flat /
    // tipped to +y, to -y; lit from (1, 1, 1) with irradiance 3 (2049 lux / 683 lm/W).
    let decode = |c: [f32; 3]| (Vec3::from(c) * (2.0 / 255.0) - Vec3::ONE).normalize();
    let e = sun(&load("normal_map.gltf"));
    assert!((e - 3.0).abs() < 1e-3, "{e}");
    let wi = Vec3::ONE.normalize();
    let lit =
        |c: [f32; 3]| Vec3::splat(1.0 + e / std::f32::consts::PI * decode(c).dot(wi).max(0.0));
    let quarters = [
        (4, 4, lit([218.0, 128.0, 218.0]), "tipped to +x"),
        (12, 4, lit([128.0, 128.0, 255.0]), "flat"),
        (4, 12, lit([128.0, 218.0, 218.0]), "tipped to +y"),
        (12, 12, lit([128.0, 37.0, 218.0]), "tipped to -y"),
    ];
    // The tips make a difference: +x and +y face the light more than flat, -y turns away.
    assert!(quarters[0].2.x > quarters[1].2.x + 0.2 && quarters[2].2.x > quarters[1].2.x + 0.2);
    assert!(quarters[3].2.x < 1.01);
    for name in ["normal_map.gltf", "normal_map_tangents.gltf"] {
        let mut s = load(name);
        assert!(s.warnings().is_empty(), "{:?}", s.warnings());
        let film = render_front(&mut s, 16, AccelKind::Sah);
        for (x, y, want, what) in quarters {
            assert_rgb(&film, x, y, want, &format!("{name}: {what}"));
        }
    }
}

#[test]
fn metallic_roughness_texture_makes_a_mirror_where_it_says() {
    let sky = Vec3::new(0.1, 0.2, 0.3);
    let film = front_under_sky("metal_rough.gltf", sky);
    // Left: rough dielectric, white diffuse under ambient 1. Right: smooth metal, a mirror
    // showing the background, no diffuse.
    assert_rgb(&film, 4, 8, Vec3::ONE, "rough dielectric");
    assert_rgb(&film, 12, 8, sky, "smooth metal");
}

#[test]
fn occlusion_texture_scales_the_ambient_term() {
    let mut s = load("occlusion.gltf");
    let film = render_front(&mut s, 16, AccelKind::Sah);
    // 1 + strength (R - 1): 0.5 for R = 0, 1 for R = 255.
    assert_rgb(&film, 4, 8, Vec3::splat(0.5), "occluded");
    assert_rgb(&film, 12, 8, Vec3::ONE, "open");
}

/// The lowest and highest view cosine over pixel `(x, y)`'s footprint on the plane z = 0 seen
/// by [`render_front`]'s camera (`size` pixels square): the jittered sample lies somewhere in it.
fn view_cosines(x: u32, y: u32, size: u32) -> (f32, f32) {
    let d = 1.0 / 20f32.to_radians().tan();
    let span = |k: u32| {
        let (a, b) = (
            -1.0 + 2.0 * k as f32 / size as f32,
            -1.0 + 2.0 * (k + 1) as f32 / size as f32,
        );
        let near = if a <= 0.0 && b >= 0.0 {
            0.0
        } else {
            a.abs().min(b.abs())
        };
        (near, a.abs().max(b.abs()))
    };
    let ((near_x, far_x), (near_y, far_y)) = (span(x), span(y));
    let cos = |u: f32, v: f32| d / (d * d + u * u + v * v).sqrt();
    (cos(far_x, far_y), cos(near_x, near_y))
}

#[test]
fn specular_extension_scales_the_highlight_by_factor_colour_and_ior() {
    // Each scene: base 0.5, roughness 0.5 (Phong exponent 2 / 0.5^4 - 2 = 30), lit head-on.
    let (n, kd, size) = (30.0, 0.5, 16);
    let scenes: Vec<Scene> = (0..4)
        .map(|i| {
            let options = LoadOptions {
                scene: Some(i),
                ..LoadOptions::default()
            };
            formats::load_with(&asset("specular.gltf"), &options).unwrap()
        })
        .collect();
    let e = sun(&scenes[0]);
    let films: Vec<Film> = scenes
        .into_iter()
        .map(|mut s| render_front(&mut s, size, AccelKind::Sah))
        .collect();
    // F0 by docs/gltf.md: 0.04 without the extension, 0 at specularFactor 0, then
    // min(((ior - 1) / (ior + 1))^2 * specularColorFactor, 1) * specularFactor.
    let ior_f0 = (0.75f32 / 2.75).powi(2);
    let tinted = Vec3::new(0.04, 0.02, 0.01) * 0.5;
    let with_ior = (Vec3::new(30.0, 1.0, 0.5) * ior_f0).min(Vec3::ONE) * 0.5;
    let lobe = e * (n + 2.0) * 0.5 / std::f32::consts::PI;
    for (x, y) in (0..size).flat_map(|y| (0..size).map(move |x| (x, y))) {
        // F0 = 0: no highlight, only ambient and Lambert.
        let base = Vec3::splat(kd * (1.0 + e / std::f32::consts::PI));
        assert_rgb(&films[1], x, y, base, "specularFactor 0");
        // The plain quad's highlight per unit F0 is the Phong lobe at this pixel's view ray.
        let q = (rgb(&films[0], x, y) - base) / 0.04;
        let (lo, hi) = view_cosines(x, y, size);
        assert!(
            q.x > lobe * lo.powf(n) * 0.999 && q.x < lobe * hi.powf(n) * 1.001,
            "pixel ({x}, {y}): lobe {q} outside {} .. {}",
            lobe * lo.powf(n),
            lobe * hi.powf(n)
        );
        assert_rgb(&films[2], x, y, base + tinted * q.x, "tinted");
        assert_rgb(
            &films[3],
            x,
            y,
            base + with_ior * q.x,
            "colour over 1, ior 1.75",
        );
    }
}

#[test]
fn clearcoat_adds_a_mirror_of_the_documented_weight() {
    let sky = Vec3::new(10.0, 20.0, 40.0);
    let film = front_under_sky("clearcoat.gltf", sky);
    // Quarters: clearcoatFactor * 0.04 * (1 - clearcoatRoughness)^2 of the background over
    // base 0.5 under ambient 1; a rough coat shows nothing (Whitted has no glossy lobe).
    let weights = [0.0, 0.04, 0.5 * 0.04 * 0.75 * 0.75, 0.0];
    for (x, y) in (0..16).flat_map(|y| (0..16).map(move |x| (x, y))) {
        let quarter = (x / 8 + 2 * (y / 8)) as usize;
        let want = Vec3::splat(0.5) + weights[quarter] * sky;
        assert_rgb(&film, x, y, want, &format!("quarter {quarter}"));
    }
}

#[test]
fn vertex_colours_in_float_u8_and_u16_multiply_the_base_colour() {
    let mut s = load("vertex_colors.gltf");
    let film = render_front(&mut s, 16, AccelKind::Sah);
    let base = Vec3::new(0.5, 1.0, 1.0);
    assert_rgb(&film, 4, 4, base * Vec3::new(1.0, 0.5, 0.25), "float VEC3");
    assert_rgb(&film, 12, 4, base * Vec3::new(0.2, 0.4, 0.6), "u8 VEC4");
    assert_rgb(&film, 4, 12, base * Vec3::new(1.0, 0.2, 0.0), "u16 VEC3");
    assert_rgb(&film, 12, 12, base, "no colours");
}

/// The 2x2 grid texture's texel `(x, y)`: red, green / blue, white.
fn grid(x: i64, y: i64) -> Vec3 {
    [[Vec3::X, Vec3::Y], [Vec3::Z, Vec3::ONE]][y as usize][x as usize]
}

#[test]
fn wrap_modes_outside_the_unit_square_and_texcoord_1() {
    let mut s = load("samplers.gltf");
    let size = 48;
    let film = render_front(&mut s, size, AccelKind::Sah);
    let wraps: [fn(i64) -> i64; 3] = [
        |i| i.rem_euclid(2),
        |i| i.clamp(0, 1),
        |i| {
            let k = i.rem_euclid(4);
            if k < 2 { k } else { 3 - k }
        },
    ];
    let mut checked = 0;
    // Top half: thirds, TEXCOORD_0 from -1 to 2 across each third.
    for py in 0..size / 2 {
        for px in 0..size {
            let (third, local) = (px / 16, px % 16);
            let t = |k: u32| -1.0 + 3.0 * k as f32 / 16.0;
            let v = |k: u32| -1.0 + 3.0 * k as f32 / 24.0;
            let (Some(i), Some(j)) = (
                texel(t(local), t(local + 1), 2.0),
                texel(v(py), v(py + 1), 2.0),
            ) else {
                continue;
            };
            let wrap = wraps[third as usize];
            assert_rgb(
                &film,
                px,
                py,
                grid(wrap(i), wrap(j)),
                &format!("wrap mode {third}"),
            );
            checked += 1;
        }
    }
    // Bottom half: TEXCOORD_1 = (1 - u, v), clamped.
    for py in size / 2..size {
        for px in 0..size {
            let u = |k: u32| 1.0 - k as f32 / 48.0;
            let v = |k: u32| (k - 24) as f32 / 24.0;
            let (Some(i), Some(j)) = (texel(u(px + 1), u(px), 2.0), texel(v(py), v(py + 1), 2.0))
            else {
                continue;
            };
            assert_rgb(&film, px, py, grid(i, j), "TEXCOORD_1");
            checked += 1;
        }
    }
    assert!(checked > 1500, "{checked} pixels checked");
}

#[test]
fn texture_transform_moves_and_scales_the_pattern() {
    let mut s = load("transform.gltf");
    let size = 32;
    let film = render_front(&mut s, size, AccelKind::Sah);
    let mut checked = 0;
    for px in 0..size {
        // u' = 2 u + 0.25 over a (black, white) 2x1 REPEAT texture.
        let u = |k: u32| 2.0 * k as f32 / 32.0 + 0.25;
        let Some(i) = texel(u(px), u(px + 1), 2.0) else {
            continue;
        };
        let want = Vec3::splat(i.rem_euclid(2) as f32);
        assert_rgb(&film, px, 16, want, "transformed stripe");
        checked += 1;
    }
    assert!(checked >= 24, "{checked}");
}

#[test]
fn quantized_mesh_matches_the_float_one() {
    let q = load("quantized.gltf");
    let f = load("quantized_float.gltf");
    assert_eq!(q.geometry().bounds(), f.geometry().bounds());
    let films: Vec<Film> = [q, f]
        .into_iter()
        .map(|s| common::render::film(s, (32, 24), AccelKind::Sah, &BuildOptions::default()))
        .collect();
    let seen = films[0].aov().iter().filter(|a| a.prim_id >= 0).count();
    assert!(seen > 100, "{seen}");
    for (a, b) in films[0].rgba().iter().zip(films[1].rgba()) {
        assert!((*a - *b).abs().max_element() < 1e-5, "{a} vs {b}");
    }
}

#[test]
fn alpha_mask_cuts_holes_for_camera_and_shadow_rays_in_every_accelerator() {
    let s = load("alpha_mask.gltf");
    let films: Vec<Film> = common::all_kinds()
        .into_iter()
        .map(|kind| render_front(&mut s.clone(), 16, kind))
        .collect();
    for (kind, film) in common::all_kinds().iter().zip(&films) {
        assert_eq!(
            film.rgba(),
            films[0].rgba(),
            "{kind:?} differs from the first kind"
        );
    }
    let film = &films[0];
    // render_front sets ambient 1: wall kd (0.2, 0.2, 1) and quad kd (1, 0.2, 0.2), each lit
    // head-on by the light's irradiance.
    let lit = 1.0 + sun(&s) / std::f32::consts::PI;
    let wall = Vec3::new(0.2, 0.2, 1.0) * lit;
    let quad = Vec3::new(1.0, 0.2, 0.2) * lit;
    // Through the hole: the wall, lit, since the light's rays pass the hole too.
    assert_rgb(film, 3, 8, wall, "wall through the hole");
    assert_rgb(film, 12, 8, quad, "opaque half");
    // Shadow rays from the wall towards the light: blocked behind the opaque half only.
    let world = World::build(s, AccelKind::Brute, &BuildOptions::default());
    let mut stats = Default::default();
    let up = |x: f32| Ray::segment(Vec3::new(x, 0.5, -0.999), Vec3::Z, 10.0);
    assert!(world.occluded(&up(0.5), &mut stats));
    assert!(!world.occluded(&up(-0.5), &mut stats));
}

#[test]
fn unused_extensions_textures_and_attributes_are_named_in_warnings_and_info() {
    let s = load("unsupported.gltf");
    let all = s.warnings().join("\n");
    for want in [
        "materials[0] \"velvet\": extension KHR_materials_sheen",
        "textures[1] (images[0]) is not used",
        "extension EXT_lumis_unknown",
        "attribute JOINTS_0",
    ] {
        assert!(all.contains(want), "no warning with {want:?} in\n{all}");
    }
    let out = Command::new(env!("CARGO_BIN_EXE_lumis"))
        .arg("info")
        .arg(asset("unsupported.gltf"))
        .output()
        .unwrap();
    common::cli::assert_ok(&out);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("warnings: 4"), "{text}");
    assert!(
        text.contains("KHR_materials_sheen") && text.contains("JOINTS_0"),
        "{text}"
    );
}
