//! `--transparent`: camera samples that escape add neither colour nor alpha, so misses are
//! A = 0, RGB = 0, silhouettes carry fractional premultiplied alpha, and comping the render
//! over the background colour gives back the opaque render; mirrors still reflect the
//! background. Without it a miss is the background colour with A = 1, unless the background
//! is black (then A = 0).

use crate::common::exr::{FlatImage, channel};
use crate::exr_passes::{CAMERA, H, W, render};

const BG: [f32; 3] = [0.2, 0.4, 0.8];
const BG_ARG: &str = "0.2,0.4,0.8";
const GLOW: [f32; 3] = [0.9, 0.5, 0.3];

/// An unlit emissive sphere on the left (its radiance is exactly `GLOW` wherever a sample
/// hits it) and a perfect mirror on the right, 4 x 4 samples per pixel for soft edges.
fn scene() -> String {
    format!(
        "{CAMERA}
[materials.glow]
diffuse = [0.0, 0.0, 0.0]
emission = {GLOW:?}

[materials.mirror]
diffuse = [0.0, 0.0, 0.0]
reflectivity = 1.0

[[sphere]]
name = \"glow\"
center = [-1.2, 0.0, 0.0]
radius = 0.8
material = \"glow\"

[[sphere]]
name = \"mirror\"
center = [1.2, 0.0, 0.0]
radius = 0.8
material = \"mirror\"
"
    )
}

fn rgba(image: &FlatImage) -> [Vec<f32>; 4] {
    ["R", "G", "B", "A"].map(|c| channel(image, c))
}

fn close(a: [f32; 3], b: [f32; 3], tol: f32) -> bool {
    a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= tol)
}

const CORNERS: [usize; 4] = [0, W - 1, (H - 1) * W, H * W - 1];
/// Pixels near the middle of each sphere's image (centres at x = 16 -+ 7.9, y = 12).
const GLOW_PX: usize = 12 * W + 8;
const MIRROR_PX: usize = 12 * W + 23;

#[test]
fn transparent_misses_are_empty_edges_premultiplied_and_comp_back_to_opaque() {
    let dir = tempfile::tempdir().unwrap();
    let args = ["--spp", "4", "--background", BG_ARG];
    let t = render(
        dir.path(),
        "s.toml",
        &scene(),
        "t.exr",
        &[&args[..], &["--transparent"]].concat(),
    );
    let o = render(dir.path(), "s.toml", &scene(), "o.exr", &args);
    let [r, g, b, a] = rgba(&t);
    let rgb = |i: usize| [r[i], g[i], b[i]];
    for i in CORNERS {
        assert_eq!((rgb(i), a[i]), ([0.0; 3], 0.0), "corner {i}");
    }
    // Solid interiors.
    assert_eq!(a[GLOW_PX], 1.0);
    assert!(close(rgb(GLOW_PX), GLOW, 1e-6), "{:?}", rgb(GLOW_PX));
    // The mirror's middle reflects the way back to the camera: nothing there but the
    // background, which it shows although camera misses are transparent.
    assert_eq!(a[MIRROR_PX], 1.0);
    assert!(close(rgb(MIRROR_PX), BG, 1e-6), "{:?}", rgb(MIRROR_PX));
    let mut edge = 0;
    for (i, &alpha) in a.iter().enumerate() {
        if alpha == 0.0 {
            assert_eq!(rgb(i), [0.0; 3], "pixel {i}: no sample hit, no colour");
        }
        // Left half: only the emissive sphere, so premultiplied colour is GLOW x coverage.
        if i % W < W / 2 {
            let want = GLOW.map(|c| c * alpha);
            assert!(
                close(rgb(i), want, 1e-6),
                "pixel {i}: {:?} vs {want:?}",
                rgb(i)
            );
            edge += usize::from(alpha > 0.0 && alpha < 1.0);
        }
    }
    assert!(
        edge >= 8,
        "{edge} anti-aliased edge pixels on the emissive sphere"
    );
    // Over the background plate (premultiplied over: C + bg (1 - A)) it is the opaque render.
    let [or, og, ob, oa] = rgba(&o);
    for i in 0..W * H {
        assert_eq!(oa[i], 1.0, "opaque render, pixel {i}");
        let comp = [0, 1, 2].map(|k| rgb(i)[k] + BG[k] * (1.0 - a[i]));
        assert!(close([or[i], og[i], ob[i]], comp, 1e-5), "pixel {i}");
    }
}

#[test]
fn without_transparent_a_miss_is_the_background_opaque_unless_black() {
    let dir = tempfile::tempdir().unwrap();
    let lit = render(
        dir.path(),
        "s.toml",
        &scene(),
        "bg.exr",
        &["--background", BG_ARG],
    );
    let black = render(dir.path(), "s.toml", &scene(), "black.exr", &[]);
    let ([r, g, b, a], [kr, kg, kb, ka]) = (rgba(&lit), rgba(&black));
    for i in CORNERS {
        assert_eq!(([r[i], g[i], b[i]], a[i]), (BG, 1.0), "corner {i}");
        assert_eq!(
            ([kr[i], kg[i], kb[i]], ka[i]),
            ([0.0; 3], 0.0),
            "corner {i}"
        );
    }
    assert_eq!((a[GLOW_PX], ka[GLOW_PX]), (1.0, 1.0));
    // A black background reflects as black: the mirror is opaque and dark.
    assert_eq!(ka[MIRROR_PX], 1.0);
    assert!(close(
        [kr[MIRROR_PX], kg[MIRROR_PX], kb[MIRROR_PX]],
        [0.0; 3],
        0.0
    ));
    // With --transparent a black background changes nothing (misses were already empty).
    let t = render(
        dir.path(),
        "s.toml",
        &scene(),
        "black_t.exr",
        &["--transparent"],
    );
    for (x, y) in rgba(&t).iter().zip(&rgba(&black)) {
        assert!(x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits()));
    }
}
