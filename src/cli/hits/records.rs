//! Batch ray queries for cross-checking against other tracers (`lumis hits`): rays in from an
//! `.npy` array, one hit record per ray out to another, plus the scene's triangles as lumis
//! sees them after loading and transforms.
//!
//! Formats (float32, C order, world space):
//! - rays `(N, 8)`: origin xyz, direction xyz (any non-zero length; `t` is in units of it),
//!   `t_min`, `t_max`; hits count in `(t_min, t_max]`.
//! - hits `(N, 9)`: `t`, primitive id, object id, barycentric `u`, `v` (weights of the
//!   triangle's second and third vertex; 0 for spheres), unit geometric normal xyz (outward for
//!   spheres, by winding for triangles), primitive kind (0 sphere, 1 triangle). A miss is
//!   `t = +inf`, ids and kind `-1`, the rest 0. Any-hit queries report the `t` of whichever
//!   blocker the traversal met first (not necessarily the nearest; `+inf` when unoccluded),
//!   ids and kind `-1`, the rest 0.
//! - triangles `(M, 10)`: primitive id, then the three world-space vertices.
//! - spheres `(K, 5)`: primitive id, world-space centre xyz, radius.
//! - spawn origins `(N, 6)`, row `i` for ray `i`: where a secondary ray leaving the hit would
//!   start under the scene's `offset` rule, on the side the ray came from (xyz, what shadow and
//!   reflection rays use) and on the far side (xyz, what refraction uses); `+inf` for misses.
//!
//! Ids are stored as float32, exact up to 2^24.

use std::io::Write;
use std::path::Path;

use npyz::WriterBuilder;
use rayon::prelude::*;

use lumis_core::accel::{Hit, TraversalStats};
use lumis_core::geometry::Primitive;
use lumis_core::math::{Ray, Vec3};
use lumis_core::scene::{Scene, World};
use lumis_io::output::{OutputError, StagedOutputs};
pub use lumis_io::rays::{RAY_COLUMNS, read_rays};

/// Floats per output hit row.
pub const HIT_COLUMNS: usize = 9;
/// Floats per triangle row.
pub const TRIANGLE_COLUMNS: usize = 10;
/// Floats per sphere row.
pub const SPHERE_COLUMNS: usize = 5;
/// Floats per spawn row.
pub const SPAWN_COLUMNS: usize = 6;

/// Rays per parallel work item: large enough to amortise scheduling, small enough to balance.
const CHUNK: usize = 1024;

/// Why a result file could not be written; it names the file.
#[derive(Debug, thiserror::Error)]
pub enum HitsError {
    /// Writing a result failed.
    #[error(transparent)]
    Write(#[from] OutputError),
}

/// Traces every ray through `world` in parallel on the current rayon pool; row `i` of the
/// result answers ray `i` (format in the module docs). Rays must have passed [`read_rays`]'s
/// checks. The result does not depend on the thread count. Primitives are intersected with the
/// scene's `precision`.
pub fn trace_rays(
    world: &World,
    rays: &[[f32; RAY_COLUMNS]],
    any_hit: bool,
) -> Vec<[f32; HIT_COLUMNS]> {
    trace_all(rays, |query, stats| query.row(world, any_hit, stats))
}

/// For every ray, the spawn origins of its hit (see the module docs); rays that miss get `inf`.
pub fn spawn_rows(world: &World, rays: &[[f32; RAY_COLUMNS]]) -> Vec<[f32; SPAWN_COLUMNS]> {
    let offset = world.scene().settings().offset;
    trace_all(rays, |query, stats| {
        match world.intersect(&query.ray, stats) {
            None => [f32::INFINITY; SPAWN_COLUMNS],
            Some(hit) => {
                let back = hit.surface.spawn_origin(-query.ray.dir, offset);
                let through = hit.surface.spawn_origin(query.ray.dir, offset);
                [back.x, back.y, back.z, through.x, through.y, through.z]
            }
        }
    })
}

/// Runs `f` over every ray in parallel chunks, keeping the input order.
fn trace_all<const N: usize>(
    rays: &[[f32; RAY_COLUMNS]],
    f: impl Fn(&Query, &mut TraversalStats) -> [f32; N] + Sync,
) -> Vec<[f32; N]> {
    let chunks: Vec<Vec<[f32; N]>> = rays
        .par_chunks(CHUNK)
        .map(|chunk| {
            let mut stats = TraversalStats::default();
            chunk
                .iter()
                .map(|r| f(&Query { ray: to_ray(r) }, &mut stats))
                .collect()
        })
        .collect();
    chunks.concat()
}

/// One ray of the batch.
struct Query {
    ray: Ray,
}

fn to_ray(r: &[f32; RAY_COLUMNS]) -> Ray {
    Ray {
        origin: Vec3::new(r[0], r[1], r[2]),
        dir: Vec3::new(r[3], r[4], r[5]),
        t_min: r[6],
        t_max: r[7],
    }
}

const MISS: [f32; HIT_COLUMNS] = [f32::INFINITY, -1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0];

impl Query {
    /// The hit row: the scene's own nearest-hit query, or for `any_hit` only the distance of
    /// the blocker the any-hit traversal stopped at.
    fn row(&self, world: &World, any_hit: bool, stats: &mut TraversalStats) -> [f32; HIT_COLUMNS] {
        let ray = &self.ray;
        if any_hit {
            let mut row = MISS;
            if let Some(t) = world.first_blocker(ray, stats) {
                row[0] = t;
            }
            return row;
        }
        let scene = world.scene();
        let g = scene.geometry();
        let Some(traced) = world.trace(ray, stats) else {
            return MISS;
        };
        // The normal on the ray the hit was found on (a far ray's was moved near the scene).
        let Hit { prim, hit } = traced.hit;
        let n = g.geometric_normal(prim, &traced.ray, &hit);
        let kind = match g.prims()[prim as usize] {
            Primitive::Sphere { .. } => 0.0,
            Primitive::Triangle { .. } => 1.0,
        };
        [
            traced.t,
            prim as f32,
            scene.object_of(prim) as f32,
            hit.u,
            hit.v,
            n.x,
            n.y,
            n.z,
            kind,
        ]
    }
}

/// Every triangle primitive of `scene` as `[prim id, v0 xyz, v1 xyz, v2 xyz]` in world space,
/// in primitive order; spheres are skipped.
pub fn triangle_rows(scene: &Scene) -> Vec<[f32; TRIANGLE_COLUMNS]> {
    let g = scene.geometry();
    g.prims()
        .iter()
        .enumerate()
        .filter_map(|(i, p)| match *p {
            Primitive::Sphere { .. } => None,
            Primitive::Triangle { mesh, tri } => {
                let [a, b, c] = g.meshes()[mesh as usize].corners(tri);
                Some([i as f32, a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z])
            }
        })
        .collect()
}

/// Every sphere primitive of `scene` as `[prim id, centre xyz, radius]` in world space, in
/// primitive order; triangles are skipped.
pub fn sphere_rows(scene: &Scene) -> Vec<[f32; SPHERE_COLUMNS]> {
    let g = scene.geometry();
    g.prims()
        .iter()
        .enumerate()
        .filter_map(|(i, p)| match *p {
            Primitive::Sphere { sphere } => {
                let s = &g.spheres()[sphere as usize];
                Some([i as f32, s.center.x, s.center.y, s.center.z, s.radius])
            }
            Primitive::Triangle { .. } => None,
        })
        .collect()
}

/// Stages `rows` as an `(len, N)` float32 C-order `.npy` array for `path` (written to a
/// temporary file beside it, renamed when the run's outputs are committed).
pub fn stage_rows<const N: usize>(
    staged: &mut StagedOutputs,
    path: &Path,
    rows: &[[f32; N]],
) -> Result<(), HitsError> {
    staged.stage(path, |w| {
        let io_err = |source| OutputError::Write {
            path: path.to_path_buf(),
            source,
        };
        let mut npy = npyz::WriteOptions::<f32>::new()
            .default_dtype()
            .shape(&[rows.len() as u64, N as u64])
            .writer(&mut *w)
            .begin_nd()
            .map_err(io_err)?;
        npy.extend(rows.iter().flatten().copied()).map_err(io_err)?;
        npy.finish().map_err(io_err)?;
        w.flush().map_err(io_err)
    })?;
    Ok(())
}
