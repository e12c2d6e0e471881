//! `lumis hits --all`: every surface crossing and graze along each ray, each crossing counted
//! once ([`World::all_hits`]; the rule is in docs/hard-cases.md, "All hits along a ray").
//!
//! Output: float32 `.npy` of shape `(M, 11)`, one row per hit, the rows of ray 0 first, then
//! ray 1's, and so on, each ray's sorted by `t` (ties by primitive id): column 0 the ray's index
//! in the input, columns 1..=9 the nearest-hit file's nine columns (`t`, primitive id, object
//! id, `u`, `v`, normal xyz, kind), column 10 the graze flag (1 for a touch that does not cross
//! the surface, 0 for a crossing). A ray without hits has no row. Indices are exact up to 2^24.

use super::records::{HIT_COLUMNS, HitsError, stage_rows, trace_rays};
use lumis_core::accel::TraversalStats;
use lumis_core::geometry::Primitive;
use lumis_core::math::{Ray, Vec3};
use lumis_core::scene::World;
use lumis_io::output::StagedOutputs;
use lumis_io::rays::RAY_COLUMNS;
use rayon::prelude::*;
use std::path::Path;

/// Floats per row of the all-hits file.
pub const ALL_HIT_COLUMNS: usize = HIT_COLUMNS + 2;

/// Rays per parallel work item (as for the nearest hits).
const CHUNK: usize = 1024;

/// What `--out` receives: one row per ray, or with `--all` one row per hit.
pub enum HitRows {
    /// The nearest-hit (or any-hit) rows, one per ray.
    Nearest(Vec<[f32; HIT_COLUMNS]>),
    /// The all-hits rows (format in the module docs).
    All(Vec<[f32; ALL_HIT_COLUMNS]>),
}

impl HitRows {
    /// Traces `rays` through `world` on the current rayon pool: every hit with `all`, else
    /// [`trace_rays`]. The result does not depend on the thread count.
    pub fn trace(world: &World, rays: &[[f32; RAY_COLUMNS]], any_hit: bool, all: bool) -> Self {
        if !all {
            return Self::Nearest(trace_rays(world, rays, any_hit));
        }
        let chunks: Vec<Vec<[f32; ALL_HIT_COLUMNS]>> = rays
            .par_chunks(CHUNK)
            .enumerate()
            .map(|(c, chunk)| {
                let mut stats = TraversalStats::default();
                let mut rows = Vec::new();
                for (i, r) in chunk.iter().enumerate() {
                    let ray = Ray {
                        origin: Vec3::new(r[0], r[1], r[2]),
                        dir: Vec3::new(r[3], r[4], r[5]),
                        t_min: r[6],
                        t_max: r[7],
                    };
                    let index = (c * CHUNK + i) as f32;
                    rows.extend(world.all_hits(&ray, &mut stats).iter().map(|h| {
                        let kind = match h.primitive {
                            Primitive::Sphere { .. } => 0.0,
                            Primitive::Triangle { .. } => 1.0,
                        };
                        [
                            index,
                            h.t,
                            h.prim as f32,
                            h.object as f32,
                            h.u,
                            h.v,
                            h.normal.x,
                            h.normal.y,
                            h.normal.z,
                            kind,
                            if h.graze { 1.0 } else { 0.0 },
                        ]
                    }));
                }
                rows
            })
            .collect();
        Self::All(chunks.concat())
    }

    /// Stages the rows for `path` (see [`stage_rows`]).
    pub fn stage(&self, staged: &mut StagedOutputs, path: &Path) -> Result<(), HitsError> {
        match self {
            Self::Nearest(rows) => stage_rows(staged, path, rows),
            Self::All(rows) => stage_rows(staged, path, rows),
        }
    }
}
