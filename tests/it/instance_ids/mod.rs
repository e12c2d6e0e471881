//! Every id output reports the instance a hit belongs to: the `lumis hits` rows with
//! `--instance-ids` (and the nine columns unchanged without it), the all-hits rows, the EXR's
//! `id.instance` channel (written, read back and merged), and the Cryptomatte object names of
//! instances.
//!
//! The scene: one prototype, a unit sphere `ball` and a quad `tile` below it, placed three times
//! along x (`copy0` at x = -3, `copy1` at 0, `copy2` at 3, the last scaled by 0.8) in front of a
//! plain `ground` triangle, all seen from +z.

mod exr;
mod hits;

use crate::common::scenes;
use glam::{DAffine3, DVec3};
use lumis_core::camera::Camera;
use lumis_core::geometry::Sphere;
use lumis_core::material::Material;
use lumis_core::math::Vec3;
use lumis_core::scene::{Part, Scene, SceneBuilder, Shape};

/// Where instance `k` sits: its centre on the x axis.
const CENTRES: [f64; 3] = [-3.0, 0.0, 3.0];
/// The ground plane's z.
const GROUND_Z: f32 = -3.0;

/// The three placements of the prototype.
fn placements() -> [DAffine3; 3] {
    CENTRES.map(|x| {
        let scale = if x > 0.0 { 0.8 } else { 1.0 };
        DAffine3::from_scale_rotation_translation(
            DVec3::splat(scale),
            glam::DQuat::IDENTITY,
            DVec3::new(x, 0.0, 0.0),
        )
    })
}

/// The scene of the module docs, `width` x `height` pixels, one sample a pixel.
fn scene(width: u32, height: u32) -> Scene {
    let mut b = SceneBuilder::new();
    let m = b.add_material(Material::default());
    let g = GROUND_Z;
    b.add_mesh(
        "ground",
        scenes::soup(&[[
            Vec3::new(-40.0, -40.0, g),
            Vec3::new(40.0, -40.0, g),
            Vec3::new(0.0, 40.0, g),
        ]]),
        m,
    );
    let (y0, y1) = (-1.8, -1.3);
    let tile = scenes::soup(&[
        [
            Vec3::new(-0.8, y0, 0.0),
            Vec3::new(0.8, y0, 0.0),
            Vec3::new(0.8, y1, 0.0),
        ],
        [
            Vec3::new(-0.8, y0, 0.0),
            Vec3::new(0.8, y1, 0.0),
            Vec3::new(-0.8, y1, 0.0),
        ],
    ]);
    let proto = b.add_prototype(vec![
        Part {
            name: "ball".into(),
            shape: Shape::Sphere(Sphere {
                center: Vec3::ZERO,
                radius: 1.0,
            }),
            material: m,
        },
        Part {
            name: "tile".into(),
            shape: Shape::Mesh(tile),
            material: m,
        },
    ]);
    for (k, p) in placements().iter().enumerate() {
        b.add_instance(proto, format!("copy{k}"), *p);
    }
    let st = b.settings_mut();
    (st.width, st.height, st.spp) = (width, height, 1);
    let camera = Camera::look_at(
        Vec3::new(0.0, 0.0, 12.0),
        Vec3::ZERO,
        Vec3::Y,
        40.0,
        0.0,
        None,
    )
    .expect("valid camera");
    b.build(camera).expect("within the limits")
}

/// The instance an object of [`scene`] belongs to, from its name alone (`copyK/part` is
/// instance K, `ground` none): what every id output must agree with.
fn instance_of_name(name: &str) -> Option<u32> {
    let (copy, _part) = name.split_once('/')?;
    copy.strip_prefix("copy")?.parse().ok()
}
