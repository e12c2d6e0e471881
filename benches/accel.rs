//! Accelerator benchmarks: SAH build throughput and single-thread closest-hit throughput on a
//! procedural ~200k-triangle bumpy sphere plus spheres, with brute force on the same scene as
//! the baseline. `cargo bench --bench accel`; results are recorded in BENCHMARKS.md.
//!
//! Before anything is timed, the SAH answers are checked against brute force (tinybvh's rule:
//! fast and checked go together).

#[path = "../tests/it/common/mod.rs"]
mod common;

use common::{Rng, brute, closest, scenes};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use lumis_core::accel::{Accel, AccelKind, BuildOptions};
use lumis_core::geometry::{Geometry, Sphere};
use lumis_core::math::{Aabb, Ray, Vec3};
use std::hint::black_box;
use std::time::Duration;

/// Rays per closest-hit measurement for the hierarchy.
const RAYS: usize = 100_000;
/// Rays per brute-force measurement: each tests all ~200k primitives, so 200 rays already take
/// about as long as 100k rays through the hierarchy.
const BRUTE_RAYS: usize = 200;

/// A bumpy sphere of 2 * 316 * 316 ~ 200k triangles and 64 spheres around it.
fn scene() -> Geometry {
    let mut g = Geometry::new();
    g.add_mesh(scenes::uv_sphere(Vec3::ZERO, 4.0, 317, 316, |d| {
        1.0 + 0.08 * (9.0 * d.x).sin() * (11.0 * d.y).cos() * (7.0 * d.z).sin()
    }));
    let mut rng = Rng::new(7);
    for _ in 0..64 {
        g.add_sphere(Sphere {
            center: rng.unit_vector() * rng.range(5.0, 9.0),
            radius: rng.range(0.2, 1.0),
        });
    }
    g
}

/// Incoherent rays: random origins in the scene box, random directions.
fn incoherent_rays(g: &Geometry, n: usize) -> Vec<Ray> {
    let mut rng = Rng::new(11);
    let b: Aabb = g.bounds();
    (0..n)
        .map(|_| Ray::new(rng.in_box(&b), rng.unit_vector()))
        .collect()
}

/// Camera-like coherent rays: a pinhole 60-degree view of the sphere, row-major over a square
/// image of about `n` pixels.
fn camera_rays(n: usize) -> Vec<Ray> {
    let side = (n as f32).sqrt().ceil() as usize;
    let eye = Vec3::new(0.0, 3.0, 14.0);
    let forward = (Vec3::ZERO - eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    let half = (30f32).to_radians().tan();
    (0..n)
        .map(|i| {
            let (x, y) = ((i % side) as f32 + 0.5, (i / side) as f32 + 0.5);
            let sx = (2.0 * x / side as f32 - 1.0) * half;
            let sy = (1.0 - 2.0 * y / side as f32) * half;
            Ray::new(eye, (forward + right * sx + up * sy).normalize())
        })
        .collect()
}

/// Traces every ray; returns the hit count so the work cannot be optimised away.
fn trace(accel: &Accel, g: &Geometry, rays: &[Ray]) -> usize {
    rays.iter()
        .filter(|r| closest(accel, g, r).is_some())
        .count()
}

fn bench(c: &mut Criterion) {
    let g = scene();
    let bounds = g.prim_bounds();
    let opts = BuildOptions::default();
    let sah = Accel::build(AccelKind::Sah, &bounds, &opts);
    let reference = brute(&g);
    let incoherent = incoherent_rays(&g, RAYS);
    let coherent = camera_rays(RAYS);
    // Validate before timing: the first brute-force batch of each ray set must agree exactly.
    for rays in [&incoherent, &coherent] {
        for r in &rays[..BRUTE_RAYS] {
            assert_eq!(closest(&sah, &g, r), closest(&reference, &g, r), "{r:?}");
        }
    }
    eprintln!(
        "scene: {} primitives ({} triangles), SAH {} nodes",
        bounds.len(),
        g.meshes()[0].triangle_count(),
        sah.node_count()
    );

    let mut group = c.benchmark_group("build");
    group.sample_size(10).warm_up_time(Duration::from_secs(1));
    group.measurement_time(Duration::from_secs(8));
    group.throughput(Throughput::Elements(bounds.len() as u64));
    group.bench_function("sah", |b| {
        b.iter(|| Accel::build(AccelKind::Sah, black_box(&bounds), &opts))
    });
    group.finish();

    let mut group = c.benchmark_group("closest_hit");
    group.sample_size(10).warm_up_time(Duration::from_secs(1));
    group.measurement_time(Duration::from_secs(5));
    for (name, rays) in [("incoherent", &incoherent), ("coherent", &coherent)] {
        group.throughput(Throughput::Elements(rays.len() as u64));
        group.bench_function(BenchmarkId::new("sah", name), |b| {
            b.iter(|| trace(&sah, &g, black_box(rays)))
        });
        let few = &rays[..BRUTE_RAYS];
        group.throughput(Throughput::Elements(few.len() as u64));
        group.bench_function(BenchmarkId::new("brute", name), |b| {
            b.iter(|| trace(&reference, &g, black_box(few)))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
