//! `lumis-lab instances-one`: one scene of `count` placements of a model, flattened or
//! instanced: load + build time, bytes held, peak RSS and (optionally) one render's time.

use anyhow::{Result, bail};
use clap::Args;
use glam::{DAffine3, DQuat, DVec3};
use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::geometry::Mesh;
use lumis_core::material::Material;
use lumis_core::render::{RenderOptions, render};
use lumis_core::scene::{Part, Scene, SceneBuilder, Shape, World, default_rig, framing_camera};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Options of `lumis-lab instances-one`.
#[derive(Args, Debug)]
pub struct InstancesOneArgs {
    /// The model file.
    model: PathBuf,
    /// Placements.
    #[arg(long)]
    count: usize,
    /// `instanced` or `flattened`.
    #[arg(long)]
    mode: String,
    /// Render once at `WxH` and report its time (0 otherwise).
    #[arg(long)]
    render: Option<String>,
    /// Instead of rendering, trace this many seeded incoherent rays (nearest hit, as
    /// `lumis hits` does) and report their time in the render column.
    #[arg(long)]
    rays: Option<usize>,
}

/// `n` incoherent rays: from points on a sphere around the scene towards points inside its
/// bounds (a fixed linear congruential sequence, so every run traces the same rays).
fn incoherent_rays(bounds: lumis_core::math::Aabb, n: usize) -> Vec<lumis_core::batch::RayRow> {
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut unit = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let c = bounds.center();
    let r = bounds.extent().length();
    (0..n)
        .map(|_| {
            let d = glam::Vec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5)
                .normalize_or(glam::Vec3::X);
            let o = c + d * r;
            let e = bounds.extent();
            let target = bounds.min + glam::Vec3::new(unit() * e.x, unit() * e.y, unit() * e.z);
            let dir = target - o;
            [o.x, o.y, o.z, dir.x, dir.y, dir.z, 0.0, f32::INFINITY]
        })
        .collect()
}

/// The meshes of a model file, in object space (the file's own transforms applied).
fn model_meshes(model: &Path) -> Result<Vec<Mesh>> {
    // The paper's `.m` meshes are not scenes by themselves.
    if model.extension().is_some_and(|e| e == "m") {
        return Ok(vec![lumis_io::formats::scn::mesh_m::load_m_file(model)?]);
    }
    let scene = lumis_io::formats::load(model)?;
    let meshes = scene.geometry().meshes().to_vec();
    if meshes.is_empty() {
        bail!("{} has no meshes", model.display());
    }
    Ok(meshes)
}

/// Triangles of one placement of the model.
pub(super) fn model_triangles(model: &Path) -> Result<u64> {
    Ok(model_meshes(model)?
        .iter()
        .map(|m| m.triangle_count() as u64)
        .sum())
}

/// Placement `i` of `count`: a square grid in the XZ plane, spaced 1.25 model sizes apart,
/// each turned by its own angle about Y (seeded by its index, so every run places alike).
fn placement(i: usize, count: usize, size: f64) -> DAffine3 {
    let side = (count as f64).sqrt().ceil() as usize;
    let (x, z) = ((i % side) as f64, (i / side) as f64);
    let angle = (i as f64 * 2.399_963).rem_euclid(std::f64::consts::TAU);
    DAffine3::from_rotation_translation(
        DQuat::from_rotation_y(angle),
        DVec3::new(x * 1.25 * size, 0.0, z * 1.25 * size),
    )
}

/// The scene of `count` placements.
fn build_scene(meshes: &[Mesh], count: usize, instanced: bool, w: u32, h: u32) -> Result<Scene> {
    let bounds = meshes
        .iter()
        .fold(lumis_core::math::Aabb::EMPTY, |b, m| b.union(m.bounds()));
    let centre = bounds.center().as_dvec3();
    let size = bounds.extent().max_element() as f64;
    let mut b = SceneBuilder::new();
    b.settings_mut().width = w;
    b.settings_mut().height = h;
    let material = b.add_material(Material::default());
    // Centred on its own origin, so turning it turns it in place.
    let recentre = DAffine3::from_translation(-centre);
    if instanced {
        let parts = meshes
            .iter()
            .enumerate()
            .map(|(k, m)| Part {
                name: k.to_string(),
                shape: Shape::Mesh(m.clone()),
                material,
            })
            .collect();
        let proto = b.add_prototype(parts);
        for i in 0..count {
            b.add_instance(
                proto,
                format!("copy{i}"),
                placement(i, count, size) * recentre,
            );
        }
    } else {
        for i in 0..count {
            let m: glam::Mat4 = glam::DMat4::from(placement(i, count, size) * recentre).as_mat4();
            for (k, mesh) in meshes.iter().enumerate() {
                b.add_mesh(
                    format!("copy{i}/{k}"),
                    mesh.clone().transformed(&m),
                    material,
                );
            }
        }
    }
    let camera = framing_camera(b.bounds(), w, h);
    for l in default_rig(b.bounds(), &camera) {
        b.add_light(l);
    }
    Ok(b.build(camera)?)
}

/// Prints "build_seconds bytes peak_bytes render_seconds triangles".
pub fn run_one(args: &InstancesOneArgs) -> Result<()> {
    let instanced = match args.mode.as_str() {
        "instanced" => true,
        "flattened" => false,
        other => bail!("--mode is instanced or flattened, not {other}"),
    };
    let (w, h) = match &args.render {
        Some(r) => match r.split_once('x').map(|(a, b)| (a.parse(), b.parse())) {
            Some((Ok(w), Ok(h))) => (w, h),
            _ => bail!("--render takes WxH, not {r}"),
        },
        None => (320, 180),
    };
    let start = Instant::now();
    let meshes = model_meshes(&args.model)?;
    let scene = build_scene(&meshes, args.count, instanced, w, h)?;
    let world = World::build(scene, AccelKind::Sah, &BuildOptions::default());
    let build = start.elapsed().as_secs_f64();
    let bytes = world.scene().geometry().bytes() + world.accel().bytes();
    let triangles: u64 = meshes
        .iter()
        .map(|m| m.triangle_count() as u64)
        .sum::<u64>()
        * args.count as u64;
    let render_s = match (&args.render, args.rays) {
        (_, Some(n)) => {
            let rays = incoherent_rays(world.scene().geometry().bounds(), n);
            let start = Instant::now();
            let hits = lumis_core::batch::trace_rays(&world, rays.as_slice(), false);
            let s = start.elapsed().as_secs_f64();
            eprintln!(
                "{} of {n} rays hit",
                hits.iter().filter(|h| h.prim.is_some()).count()
            );
            s
        }
        (Some(_), None) => {
            let start = Instant::now();
            let r = render(&world, &RenderOptions::default())?;
            std::hint::black_box(&r);
            start.elapsed().as_secs_f64()
        }
        (None, None) => 0.0,
    };
    let peak = crate::load::files::peak_rss_bytes().unwrap_or(0);
    println!("{build} {bytes} {peak} {render_s} {triangles}");
    Ok(())
}
