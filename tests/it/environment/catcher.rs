//! The shadow catcher composites onto a plate: a render with the ground as a catcher, put
//! `over` a plate image, equals a render where the ground itself has the plate's colours,
//! lit so that it shows the plate exactly where nothing shadows it.
//!
//! The camera looks straight down (orthographic), so the plate's two halves (x < 0 and
//! x > 0 in the world, the left and right halves of the image) are the two colours of the
//! reference ground. Its lighting adds up to 1 (`ambient + E cos / pi = 1`), the condition
//! under which a plate photographed without the model, multiplied by the catcher's shadow,
//! is what the scene would look like: `plate * (A_amb + visible E cos) / (A_amb + E cos)`.
//! Tolerance 1e-5: the two sides compute the same products in a different order.

use crate::common::exr::{FlatImage, channel};
use crate::exr_passes::{H, W, at, render};

const P1: [f32; 3] = [0.8, 0.5, 0.3];
const P2: [f32; 3] = [0.2, 0.6, 0.9];
const AMBIENT: f32 = 0.3;

fn scene(ground: &str) -> String {
    // Light straight down but tilted: E cos(theta) / pi = 1 - AMBIENT on the ground.
    let d = [0.3f32, -1.0, 0.2];
    let cos = 1.0 / (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let e = (1.0 - AMBIENT) * std::f32::consts::PI / cos;
    format!(
        r#"
[render]
spp = 3
ambient = [{AMBIENT}, {AMBIENT}, {AMBIENT}]
background = [0.0, 0.0, 0.0]
[camera]
type = "orthographic"
height = 6.0
position = [0.0, 10.0, 0.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 0.0, -1.0]
[materials.ball]
diffuse = [0.5, 0.4, 0.3]
{ground}
[[light]]
type = "directional"
direction = {d:?}
intensity = {e}
[[sphere]]
center = [0.5, 1.5, 0.3]
radius = 1.0
material = "ball"
"#
    )
}

fn quad(x0: f32, x1: f32, material: &str) -> String {
    format!(
        r#"
[[mesh]]
positions = [[{x0}, 0.0, -5.0], [{x1}, 0.0, -5.0], [{x1}, 0.0, 5.0], [{x0}, 0.0, 5.0]]
indices = [[0, 2, 1], [0, 3, 2]]
material = "{material}"
"#
    )
}

fn rgba(image: &FlatImage, i: usize) -> [f32; 4] {
    ["R", "G", "B", "A"].map(|c| channel(image, c)[i])
}

#[test]
fn the_catcher_over_a_plate_equals_the_plate_as_a_lit_ground() {
    let dir = tempfile::tempdir().unwrap();
    let catcher = format!(
        "{}\n[materials.catcher]\nshadow_catcher = true\n{}{}",
        scene(""),
        quad(-5.0, 0.0, "catcher"),
        quad(0.0, 5.0, "catcher")
    );
    let reference = format!(
        "{}\n[materials.p1]\ndiffuse = {P1:?}\n[materials.p2]\ndiffuse = {P2:?}\n{}{}",
        scene(""),
        quad(-5.0, 0.0, "p1"),
        quad(0.0, 5.0, "p2")
    );
    let caught = render(dir.path(), "c.toml", &catcher, "c.exr", &["--transparent"]);
    let want = render(dir.path(), "r.toml", &reference, "r.exr", &[]);
    let shadow: Vec<Vec<f32>> = ["R", "G", "B"]
        .iter()
        .map(|c| channel(&caught, &format!("shadow.{c}")))
        .collect();
    let (mut shadowed, mut lit) = (0, 0);
    for y in 0..H {
        for x in (0..W).filter(|x| !(W / 2 - 1..=W / 2).contains(x)) {
            let i = at(x, y);
            let plate = if x < W / 2 { P1 } else { P2 };
            let [r, g, b, a] = rgba(&caught, i);
            let over = [r, g, b]
                .iter()
                .zip(plate)
                .map(|(c, p)| c + p * (1.0 - a))
                .collect::<Vec<_>>();
            let w = rgba(&want, i);
            for k in 0..3 {
                assert!(
                    (over[k] - w[k]).abs() <= 1e-5 * w[k].abs().max(1.0),
                    "pixel ({x}, {y}) channel {k}: catcher over plate {} vs lit plate {}",
                    over[k],
                    w[k]
                );
            }
            // Where only the catcher is seen, the shadow pass is what multiplies the plate.
            if channel(&caught, "id.object")[i] >= 1.0 && r == 0.0 {
                assert!(
                    (shadow[0][i] - (1.0 - a)).abs() < 1e-5,
                    "shadow pass at {x},{y}"
                );
                if a > 0.5 {
                    shadowed += 1;
                } else if a == 0.0 {
                    lit += 1;
                }
            }
        }
    }
    assert!(shadowed > 10 && lit > 10, "shadowed {shadowed}, lit {lit}");
}

#[test]
fn without_transparent_the_catcher_shows_the_background_darkened() {
    let dir = tempfile::tempdir().unwrap();
    let scene = format!(
        "{}\n[materials.catcher]\nshadow_catcher = true\n{}",
        scene("").replace(
            "background = [0.0, 0.0, 0.0]",
            "background = [0.5, 0.5, 0.5]"
        ),
        quad(-5.0, 5.0, "catcher")
    );
    let image = render(dir.path(), "c.toml", &scene, "c.exr", &[]);
    let shadow = channel(&image, "shadow.R");
    let ids = channel(&image, "id.object");
    let mut seen = 0;
    for i in 0..W * H {
        let [r, _, _, a] = rgba(&image, i);
        if ids[i] >= 1.0 && shadow[i] < 1.0 && (r - 0.5 * shadow[i]).abs() < 1e-6 {
            assert_eq!(a, 1.0);
            seen += 1;
        }
    }
    assert!(seen > 10, "{seen} pixels show the darkened background");
}
