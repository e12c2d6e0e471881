//! The scenes `lumis-lab accuracy` measures: the built-in default, three paper scenes, one
//! mesh asset and two hard cases far from the origin that are built here in code.

use anyhow::{Context, Result, bail};
use lumis_core::camera::Camera;
use lumis_core::geometry::{Mesh, Sphere};
use lumis_core::light::Light;
use lumis_core::material::{Material, Texture};
use lumis_core::math::Vec3;
use lumis_core::scene::{Scene, SceneBuilder};
use std::path::Path;

/// A scene with the name its rows carry.
#[derive(Clone, Debug)]
pub struct BenchScene {
    /// Short name (file name or built-in name).
    pub name: String,
    /// The scene; its settings are overwritten by each sweep point.
    pub scene: Scene,
}

/// Names accepted besides file paths.
pub const BUILTIN: [&str; 3] = ["default", "far-occluder", "far-spheres"];

/// The paper scenes of the default set: glass and mirrors (allMaterials), noise textures
/// (texturesInYoFace), textured spheres inside huge triangles (tumbledStones).
pub const PAPER: [&str; 3] = [
    "allMaterials.scn",
    "texturesInYoFace.scn",
    "tumbledStones.scn",
];

/// The mesh-heavy asset of the default set, relative to the workspace root.
pub const MESH_ASSET: &str = "assets/knot.obj";

/// The default set; paper scenes missing from `paper_dir` are skipped with a warning so the
/// command still runs outside the project's shared data.
pub fn default_set(paper_dir: &Path) -> Result<Vec<BenchScene>> {
    let mut out = vec![resolve("default", paper_dir)?];
    for f in PAPER {
        let path = paper_dir.join(f);
        if path.exists() {
            out.push(resolve(&path.to_string_lossy(), paper_dir)?);
        } else {
            eprintln!("warning: {} not found, skipped", path.display());
        }
    }
    // This crate is crates/lab of the workspace; the asset is the workspace's.
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(MESH_ASSET);
    if mesh.exists() {
        out.push(resolve(&mesh.to_string_lossy(), paper_dir)?);
    } else {
        eprintln!("warning: {} not found, skipped", mesh.display());
    }
    out.push(resolve("far-occluder", paper_dir)?);
    out.push(resolve("far-spheres", paper_dir)?);
    Ok(out)
}

/// A built-in name, a paper scene's file name (looked up in `paper_dir`), or a scene path.
pub fn resolve(arg: &str, paper_dir: &Path) -> Result<BenchScene> {
    let scene = match arg {
        "default" => lumis_io::formats::default_scene().context("loading the default scene")?,
        "far-occluder" => far_occluder(),
        "far-spheres" => far_spheres(),
        _ => {
            let direct = Path::new(arg);
            let path = if direct.exists() {
                direct.to_path_buf()
            } else if paper_dir.join(arg).exists() {
                paper_dir.join(arg)
            } else {
                bail!("{arg}: no such file, and not one of {}", BUILTIN.join(", "));
            };
            lumis_io::formats::load(&path).with_context(|| format!("loading {}", path.display()))?
        }
    };
    let name = Path::new(arg)
        .file_name()
        .map_or_else(|| arg.to_string(), |n| n.to_string_lossy().into_owned());
    Ok(BenchScene { name, scene })
}

/// Two triangles of the square of half-size `h` around `c` in the plane y = `c.y`.
fn quad(c: Vec3, h: f32) -> Mesh {
    let p = |dx: f32, dz: f32| Vec3::new(c.x + dx, c.y, c.z + dz);
    let positions = vec![p(-h, -h), p(h, h), p(h, -h), p(-h, h)];
    Mesh::new(positions, None, None, vec![[0, 1, 2], [0, 3, 1]]).expect("a valid quad")
}

/// The offsets hard case rendered: a ground square 1.8e6 wide around (1e6, -1e6, 1e6), where one
/// ulp is 0.0625, with a square occluder hovering 0.5 above it under a low directional light (so its
/// shadow falls in view), plus a mirror sphere resting on the ground. A fixed-ulp offset lifts
/// shadow rays over the occluder; f32 Moller-Trumbore leaks along the quads' diagonals.
pub fn far_occluder() -> Scene {
    let base = Vec3::new(1e6, -1e6, 1e6);
    // Occluder half-size: 64 ulps of the coordinates, so its shadow is wider than their rounding.
    let h = 4.0;
    let mut b = SceneBuilder::new();
    b.settings_mut().ambient = Vec3::splat(0.05);
    let ground = b.add_material(Material {
        diffuse: Texture::Checkerboard {
            a: Vec3::splat(0.7),
            b: Vec3::splat(0.35),
            scale: 8.0,
            origin: Vec3::ZERO,
        },
        ..Material::default()
    });
    let grey = b.add_material(Material {
        diffuse: Texture::Solid(Vec3::new(0.7, 0.3, 0.2)),
        ..Material::default()
    });
    let mirror = b.add_material(Material {
        diffuse: Texture::Solid(Vec3::splat(0.1)),
        reflectivity: 0.8,
        ..Material::default()
    });
    // Two huge triangles, as in the paper's pits and stone scenes: f32 Moller-Trumbore's `t`
    // then errs by ~1e-7 of the triangle's size (0.01 units here), enough to start shadow rays
    // under the ground; the watertight test's f64 plane distance does not.
    b.add_mesh("ground", quad(base, 9e5), ground);
    b.add_mesh("occluder", quad(base + Vec3::Y * 0.5, h), grey);
    b.add_sphere(
        "mirror",
        Sphere {
            center: base + Vec3::new(-6.0, 3.0, -8.0),
            radius: 3.0,
        },
        mirror,
    );
    let wi = Vec3::new(0.8, 0.3 * 2.0 / h, 0.1).normalize();
    b.add_light(Light::Directional {
        direction: -wi,
        irradiance: Vec3::splat(3.0),
    });
    let cam = Camera::look_at(
        base + Vec3::new(16.0, 40.0, 4.0) * 0.6,
        base + Vec3::new(-2.0, 0.0, -2.0),
        Vec3::Y,
        45.0,
        0.0,
        None,
    )
    .expect("a valid camera");
    b.build(cam)
        .expect("the accuracy scenes are within the value limits")
}

/// A huge ground sphere (radius 1e7, like the paper's) whose top is at (1e5, 0, -1e5), with a glass, a mirror
/// and a diffuse sphere resting on it under a point light: curvature and cancellation in the
/// sphere test far from the origin, refraction and reflection chains near a huge surface.
pub fn far_spheres() -> Scene {
    let base = Vec3::new(1e5, 0.0, -1e5);
    let mut b = SceneBuilder::new();
    b.settings_mut().ambient = Vec3::splat(0.05);
    let ground = b.add_material(Material {
        diffuse: Texture::Checkerboard {
            a: Vec3::splat(0.8),
            b: Vec3::new(0.2, 0.3, 0.5),
            scale: 1.0,
            origin: Vec3::ZERO,
        },
        ..Material::default()
    });
    let glass = b.add_material(Material {
        diffuse: Texture::Solid(Vec3::ZERO),
        transmission: 0.9,
        ior: 1.5,
        ..Material::default()
    });
    let mirror = b.add_material(Material {
        diffuse: Texture::Solid(Vec3::splat(0.05)),
        reflectivity: 0.9,
        ..Material::default()
    });
    let red = b.add_material(Material {
        diffuse: Texture::Solid(Vec3::new(0.8, 0.2, 0.1)),
        specular: Vec3::splat(0.3),
        shininess: 40.0,
        ..Material::default()
    });
    let r = 1e7;
    b.add_sphere(
        "ground",
        Sphere {
            center: base - Vec3::Y * r,
            radius: r,
        },
        ground,
    );
    for (name, c, radius, m) in [
        ("glass", Vec3::new(0.0, 1.0, 0.0), 1.0, glass),
        ("mirror", Vec3::new(2.5, 1.2, -1.5), 1.2, mirror),
        ("diffuse", Vec3::new(-2.2, 0.6, 0.8), 0.6, red),
    ] {
        b.add_sphere(
            name,
            Sphere {
                center: base + c,
                radius,
            },
            m,
        );
    }
    b.add_light(Light::Point {
        position: base + Vec3::new(3.0, 10.0, 5.0),
        intensity: Vec3::splat(250.0),
    });
    let cam = Camera::look_at(
        base + Vec3::new(0.0, 3.0, 9.0),
        base + Vec3::new(0.0, 0.8, 0.0),
        Vec3::Y,
        40.0,
        0.0,
        None,
    )
    .expect("a valid camera");
    b.build(cam)
        .expect("the accuracy scenes are within the value limits")
}

#[cfg(test)]
mod mesh_asset_tests {
    use super::*;

    #[test]
    fn the_default_set_finds_its_mesh() {
        let set = default_set(Path::new("/nonexistent")).unwrap();
        assert!(
            set.iter().any(|s| s.name == "knot.obj"),
            "{:?}",
            set.iter().map(|s| &s.name).collect::<Vec<_>>()
        );
    }
}
