//! `albedo.R/G/B`: the material's diffuse colour `kd` at the centre ray's hit, textures
//! evaluated there, never lit; 0 where the centre ray misses.

use std::path::Path;

use crate::common::exr::channel;
use crate::exr_passes::{CAMERA, H, W, at, render};

/// A red Lambert sphere filling the middle of the image, lit by `light`.
fn sphere_scene(light: &str) -> String {
    format!(
        "{CAMERA}
[materials.red]
diffuse = [0.7, 0.2, 0.1]

[[sphere]]
name = \"ball\"
center = [0.0, 0.0, 0.0]
radius = 1.0
material = \"red\"

{light}"
    )
}

const KEY: &str = "[[light]]
type = \"point\"
position = [3.0, 4.0, 5.0]
intensity = 100.0";

const DIM_FROM_BELOW: &str = "[[light]]
type = \"point\"
position = [-4.0, -3.0, 2.0]
color = [0.2, 0.5, 1.0]
intensity = 3.0";

fn albedo(image: &crate::common::exr::FlatImage) -> [Vec<f32>; 3] {
    ["albedo.R", "albedo.G", "albedo.B"].map(|c| channel(image, c))
}

#[test]
fn albedo_is_the_diffuse_colour_on_hits_and_zero_on_misses() {
    let dir = tempfile::tempdir().unwrap();
    let image = render(
        dir.path(),
        "s.toml",
        &sphere_scene(KEY),
        "a.exr",
        &["--aov", "albedo"],
    );
    let [r, g, b] = albedo(&image);
    let id = channel(&image, "id.object");
    // The pixel just below-right of the image centre looks at the sphere's front.
    let c = at(W / 2, H / 2);
    assert_eq!([r[c], g[c], b[c]], [0.7, 0.2, 0.1]);
    // The corners see nothing.
    for i in [at(0, 0), at(W - 1, 0), at(0, H - 1), at(W - 1, H - 1)] {
        assert_eq!(id[i], -1.0);
        assert_eq!([r[i], g[i], b[i]], [0.0; 3], "miss at {i}");
    }
    // Every pixel: kd exactly where the centre ray hit, 0 where it missed.
    let hits = id.iter().filter(|&&o| o >= 0.0).count();
    assert!(hits > 50 && hits < W * H - 50, "{hits} hits");
    for i in 0..W * H {
        let want = if id[i] >= 0.0 {
            [0.7, 0.2, 0.1]
        } else {
            [0.0; 3]
        };
        assert_eq!([r[i], g[i], b[i]], want, "pixel {i}");
    }
}

#[test]
fn albedo_is_not_lit() {
    let dir = tempfile::tempdir().unwrap();
    let a = render(
        dir.path(),
        "a.toml",
        &sphere_scene(KEY),
        "a.exr",
        &["--aov", "albedo"],
    );
    let b = render(
        dir.path(),
        "b.toml",
        &sphere_scene(DIM_FROM_BELOW),
        "b.exr",
        &["--aov", "albedo"],
    );
    // The beauty changed (the light moved, dimmed and turned blue) ...
    let (ra, rb) = (channel(&a, "R"), channel(&b, "R"));
    let changed = ra.iter().zip(&rb).filter(|(x, y)| x != y).count();
    assert!(
        changed > 50,
        "only {changed} pixels changed: the test sees no lighting"
    );
    // ... the albedo did not, bit for bit.
    for (ca, cb) in albedo(&a).iter().zip(&albedo(&b)) {
        assert!(ca.iter().zip(cb).all(|(x, y)| x.to_bits() == y.to_bits()));
    }
}

/// sRGB byte to linear, written out from IEC 61966-2-1 (not lumis's function).
fn srgb_byte_to_linear(b: u8) -> f64 {
    let c = b as f64 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The texture's four 2x2-texel quadrants, top-left, top-right, bottom-left, bottom-right.
const QUADRANTS: [[u8; 3]; 4] = [[200, 30, 90], [10, 220, 128], [64, 64, 255], [255, 255, 0]];
/// `Kd`, which lumis multiplies the texture by.
const TINT: [f64; 3] = [0.5, 1.0, 0.25];

/// A 2x2 quad in the z = 0 plane facing the camera, its uvs spanning the texture once, with an
/// MTL material whose `map_Kd` is a 4x4 PNG of four flat quadrants.
fn write_textured_quad(dir: &Path) {
    let png = image::RgbImage::from_fn(4, 4, |x, y| {
        image::Rgb(QUADRANTS[(x / 2 + 2 * (y / 2)) as usize])
    });
    png.save(dir.join("tex.png")).unwrap();
    std::fs::write(
        dir.join("quad.mtl"),
        format!(
            "newmtl checker\nKd {} {} {}\nmap_Kd tex.png\n",
            TINT[0], TINT[1], TINT[2]
        ),
    )
    .unwrap();
    // OBJ's v = 0 is the image's bottom; lumis stores 1 - v, so uv (0, 0) is the top-left
    // corner (-1, 1), as the image is seen.
    std::fs::write(
        dir.join("quad.obj"),
        "mtllib quad.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
         vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl checker\nf 1/1 2/2 3/3 4/4\n",
    )
    .unwrap();
}

/// The textured quad, close enough to fill most of the image.
pub fn textured_quad_scene(dir: &Path) -> String {
    write_textured_quad(dir);
    "[render]\nspp = 1\n\n[camera]\nposition = [0.0, 0.0, 2.6]\nlook_at = [0.0, 0.0, 0.0]\n\
     fov = 40.0\n\n[[light]]\ntype = \"point\"\nposition = [0.0, 1.0, 3.0]\nintensity = 30.0\n\n\
     [[mesh]]\nname = \"quad\"\nfile = \"quad.obj\"\n"
        .to_string()
}

#[test]
fn a_textured_albedo_is_the_texture_at_the_hit() {
    let dir = tempfile::tempdir().unwrap();
    let scene = textured_quad_scene(dir.path());
    let image = render(
        dir.path(),
        "q.toml",
        &scene,
        "q.exr",
        &["--aov", "albedo,uv"],
    );
    let [r, g, b] = albedo(&image);
    let (u, v) = (channel(&image, "uv.U"), channel(&image, "uv.V"));
    let id = channel(&image, "id.object");
    // Where the centre ray's uv is at least a texel's half from a quadrant's edge, bilinear
    // filtering reads four texels of one colour: the albedo is that colour times Kd.
    let flat = |t: f32| {
        let f = (t * 4.0).rem_euclid(2.0);
        (0.5..1.5).contains(&f)
    };
    let mut seen = [0; 4];
    for i in 0..W * H {
        if id[i] < 0.0 {
            assert_eq!([r[i], g[i], b[i]], [0.0; 3]);
            continue;
        }
        if !(flat(u[i]) && flat(v[i])) {
            continue;
        }
        let q = usize::from(u[i] >= 0.5) + 2 * usize::from(v[i] >= 0.5);
        seen[q] += 1;
        for (k, got) in [r[i], g[i], b[i]].into_iter().enumerate() {
            let want = srgb_byte_to_linear(QUADRANTS[q][k]) * TINT[k];
            assert!(
                (got as f64 - want).abs() < 2e-6,
                "pixel {i} uv ({}, {}) quadrant {q}: {got} vs {want}",
                u[i],
                v[i]
            );
        }
    }
    assert!(seen.iter().all(|&n| n >= 4), "pixels per quadrant {seen:?}");
    // The quadrants appear where the image shows them: top-left quadrant at the top-left.
    let (tl, br) = (at(W / 2 - 4, H / 2 - 4), at(W / 2 + 3, H / 2 + 3));
    assert!(u[tl] < 0.5 && v[tl] < 0.5, "({}, {})", u[tl], v[tl]);
    assert!(u[br] > 0.5 && v[br] > 0.5, "({}, {})", u[br], v[br]);
}
