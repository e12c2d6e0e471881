//! `P.X/Y/Z`: the world-space point the centre ray of each pixel hit, checked three ways: it
//! projects through the header's `worldToNDC` onto that pixel's centre, it lies on the
//! analytic surface, and its distance along the view axis is the pixel's `Z`.

use std::collections::BTreeMap;

use crate::common::exr::channel;
use crate::exr_passes::{H, W, render, row_times_m44f};

const EYE: [f64; 3] = [0.5, 1.5, 5.0];
const LOOK_AT: [f64; 3] = [0.0, -0.2, 0.0];
const CENTRE: [f64; 3] = [0.3, 0.2, 0.0];
const RADIUS: f64 = 1.0;
const GROUND: f32 = -1.0;

/// A sphere above a ground quad at y = -1, seen from above at an angle (no axis-aligned view),
/// sky at the top of the image.
fn scene() -> String {
    format!(
        "[render]\nspp = 1\n\n[camera]\nposition = {EYE:?}\nlook_at = {LOOK_AT:?}\nfov = 40.0\n\n\
         [[light]]\ntype = \"directional\"\ndirection = [0.0, -1.0, -0.5]\nintensity = 1.0\n\n\
         [[sphere]]\nname = \"ball\"\ncenter = {CENTRE:?}\nradius = {RADIUS:?}\n\n\
         [[mesh]]\nname = \"ground\"\n\
         positions = [[-20.0, {GROUND:?}, -20.0], [20.0, {GROUND:?}, -20.0], \
         [20.0, {GROUND:?}, 20.0], [-20.0, {GROUND:?}, 20.0]]\n\
         indices = [[0, 2, 1], [0, 3, 2]]\n"
    )
}

#[test]
fn position_reprojects_lies_on_the_surface_and_agrees_with_z() {
    let dir = tempfile::tempdir().unwrap();
    let image = render(
        dir.path(),
        "p.toml",
        &scene(),
        "p.exr",
        &["--aov", "position"],
    );
    let p = ["P.X", "P.Y", "P.Z"].map(|c| channel(&image, c));
    let (z, id) = (channel(&image, "Z"), channel(&image, "id.object"));
    let w2ndc = image.layer_data[0]
        .attributes
        .world_to_normalized_device
        .expect("worldToNDC");
    let forward = {
        let d: [f64; 3] = std::array::from_fn(|k| LOOK_AT[k] - EYE[k]);
        let len = d.iter().map(|c| c * c).sum::<f64>().sqrt();
        d.map(|c| c / len)
    };
    let mut by_object: BTreeMap<i64, Vec<[f32; 3]>> = BTreeMap::new();
    for y in 0..H {
        for x in 0..W {
            let i = y * W + x;
            let pt = [p[0][i], p[1][i], p[2][i]];
            if id[i] < 0.0 {
                assert_eq!(pt, [0.0; 3], "miss ({x}, {y})");
                assert_eq!(z[i], f32::INFINITY);
                continue;
            }
            // Back through the header's camera: onto the pixel centre.
            let q = row_times_m44f([pt[0], pt[1], pt[2], 1.0], &w2ndc);
            let (px, py) = (q[0] / q[3] * W as f32, q[1] / q[3] * H as f32);
            assert!(
                (px - (x as f32 + 0.5)).abs() < 1e-3 && (py - (y as f32 + 0.5)).abs() < 1e-3,
                "({x}, {y}): P {pt:?} projects to ({px}, {py})"
            );
            // Z is the distance along the camera's forward axis.
            let along: f64 = (0..3).map(|k| (pt[k] as f64 - EYE[k]) * forward[k]).sum();
            assert!(
                (along - z[i] as f64).abs() < 1e-5 * along,
                "({x}, {y}): Z {} vs (P - eye) . forward {along}",
                z[i]
            );
            by_object.entry(id[i] as i64).or_default().push(pt);
        }
    }
    assert_eq!(by_object.len(), 2, "the sphere and the ground are seen");
    let (mut ground, mut ball) = (0, 0);
    for points in by_object.values() {
        if points.iter().all(|pt| pt[1] == GROUND) {
            // Every corner of the ground has y = -1 exactly, so the point does too.
            ground += points.len();
        } else {
            for pt in points {
                let r = (0..3)
                    .map(|k| (pt[k] as f64 - CENTRE[k]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                assert!((r - RADIUS).abs() < 1e-6, "{pt:?} is {r} from the centre");
            }
            ball += points.len();
        }
    }
    assert!(
        ground > 50 && ball > 50,
        "ground {ground}, ball {ball} pixels"
    );
    assert!(id[..W].iter().all(|&o| o < 0.0), "the top row is sky");
}
