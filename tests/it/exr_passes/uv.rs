//! `uv.U/V`: the texture coordinates at the centre ray's hit. On a mesh, the interpolation of
//! its vertices' uvs (the OBJ's `vt`, with lumis's top-left origin); on a sphere, lumis's
//! documented longitude/latitude convention `u = (atan2(z, x) + pi) / 2pi`,
//! `v = acos(y / r) / pi` about the centre (y up, so v = 0 at the top pole).

use std::f64::consts::PI;

use crate::common::exr::channel;
use crate::exr_passes::albedo::textured_quad_scene;
use crate::exr_passes::{CAMERA, H, W, at, render};

#[test]
fn quad_uv_is_the_analytic_interpolation_at_the_pixel_centre() {
    let dir = tempfile::tempdir().unwrap();
    let scene = textured_quad_scene(dir.path());
    let image = render(dir.path(), "q.toml", &scene, "q.exr", &["--aov", "uv"]);
    let (u, v) = (channel(&image, "uv.U"), channel(&image, "uv.V"));
    let id = channel(&image, "id.object");
    // The pinhole ray through pixel centre (x + 0.5, y + 0.5) meets the plane z = 0 at
    // (X, Y) = (ndc_x * aspect, ndc_y) * tan(fov / 2) * distance; the quad maps (-1, 1) to
    // uv (0, 0) and (1, -1) to uv (1, 1), affinely.
    let (tan, dist, aspect) = ((20f64).to_radians().tan(), 2.6, W as f64 / H as f64);
    let mut inside = 0;
    for y in 0..H {
        for x in 0..W {
            let wx = (2.0 * (x as f64 + 0.5) / W as f64 - 1.0) * tan * aspect * dist;
            let wy = (1.0 - 2.0 * (y as f64 + 0.5) / H as f64) * tan * dist;
            let i = at(x, y);
            if wx.abs().max(wy.abs()) > 0.99 {
                continue;
            }
            inside += 1;
            assert!(id[i] >= 0.0, "({x}, {y}) should see the quad");
            let want = ((wx + 1.0) / 2.0, (1.0 - wy) / 2.0);
            assert!(
                (u[i] as f64 - want.0).abs() < 1e-5 && (v[i] as f64 - want.1).abs() < 1e-5,
                "({x}, {y}): uv ({}, {}) vs {want:?}",
                u[i],
                v[i]
            );
        }
    }
    assert!(inside > 300, "{inside} pixels on the quad");
    // Misses are 0.
    assert_eq!((u[at(0, 0)], v[at(0, 0)]), (0.0, 0.0));
}

#[test]
fn sphere_uv_is_longitude_and_latitude() {
    let dir = tempfile::tempdir().unwrap();
    let scene = format!(
        "{CAMERA}\n[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.5\n\n\
         [[light]]\ntype = \"directional\"\ndirection = [0.0, 0.0, -1.0]\nintensity = 1.0\n"
    );
    let image = render(
        dir.path(),
        "s.toml",
        &scene,
        "s.exr",
        &["--aov", "uv,position"],
    );
    let (u, v) = (channel(&image, "uv.U"), channel(&image, "uv.V"));
    let p = ["P.X", "P.Y", "P.Z"].map(|c| channel(&image, c));
    let id = channel(&image, "id.object");
    let mut hits = 0;
    for i in (0..W * H).filter(|&i| id[i] >= 0.0) {
        hits += 1;
        let (x, y, z) = (p[0][i] as f64, p[1][i] as f64, p[2][i] as f64);
        let want_u = (z.atan2(x) + PI) / (2.0 * PI);
        let want_v = (y / 1.5).clamp(-1.0, 1.0).acos() / PI;
        // u wraps at the seam (the -x meridian): compare on the circle.
        let du = (u[i] as f64 - want_u).rem_euclid(1.0);
        assert!(
            du.min(1.0 - du) < 1e-5 && (v[i] as f64 - want_v).abs() < 1e-5,
            "pixel {i} P ({x}, {y}, {z}): uv ({}, {}) vs ({want_u}, {want_v})",
            u[i],
            v[i]
        );
    }
    assert!(hits > 100, "{hits} hits");
    // The front of the sphere (+z, towards the camera) is u = 3/4, the equator v = 1/2; v falls
    // towards the top pole and u towards +x.
    let c = at(W / 2, H / 2);
    assert!(
        (u[c] - 0.75).abs() < 0.02 && (v[c] - 0.5).abs() < 0.04,
        "{} {}",
        u[c],
        v[c]
    );
    assert!(v[at(W / 2, H / 2 - 5)] < v[c] - 0.05);
    assert!(u[at(W / 2 + 5, H / 2)] < u[c] - 0.05);
}
