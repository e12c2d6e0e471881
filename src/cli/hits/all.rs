//! `lumis hits --all`: every surface crossing and graze along each ray, each crossing counted
//! once ([`lumis_core::scene::World::all_hits`]; the rule is in docs/hard-cases.md, "All hits
//! along a ray"), through the library's batch query ([`trace_all_hits`], shared with the
//! Python package).
//!
//! Output: float32 `.npy` of shape `(M, 11)`, one row per hit, the rows of ray 0 first, then
//! ray 1's, and so on, each ray's sorted by `t` (ties by primitive id): column 0 the ray's index
//! in the input, columns 1..=9 the nearest-hit file's nine columns (`t`, primitive id, object
//! id, `u`, `v`, normal xyz, kind), column 10 the graze flag (1 for a touch that does not cross
//! the surface, 0 for a crossing). A ray without hits has no row. Indices are exact up to 2^24.
//! With `--instance-ids`, `(M, 12)`: column 11 the instance id (-1 outside any instance).

use super::records::{HitsError, stage_rows};
use lumis_core::batch::{
    AllHitRecord, HitRecord, RayRow, trace_all_hits, trace_packets_into, trace_rays,
    trace_rays_into,
};
use lumis_core::scene::World;
use lumis_io::output::StagedOutputs;
use std::path::Path;

/// Which query `lumis hits` runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Query {
    /// The nearest hit, one ray at a time.
    Nearest,
    /// The nearest hit, groups of eight rays walked as packets where they can be (`--packets`).
    Packets,
    /// Any hit (`--any-hit`).
    AnyHit,
    /// Every hit (`--all`).
    All,
}

/// What `--out` receives: one record per ray, or with `--all` one per hit.
pub enum HitRows {
    /// The nearest-hit (or any-hit) records, one per ray.
    Nearest(Vec<HitRecord>),
    /// The all-hits records (format in the module docs).
    All(Vec<AllHitRecord>),
}

impl HitRows {
    /// Traces `rays` through `world` on the current rayon pool: every hit with `all`, else
    /// [`trace_rays`]; the result does not depend on the thread count. Into this value's memory
    /// where it can (`--repeat`: each run after the first then times the queries, not fresh
    /// page faults for the records).
    pub fn retrace(self, world: &World, rays: &[RayRow], query: Query) -> Self {
        match (self, query) {
            (_, Query::All) => Self::All(trace_all_hits(world, rays)),
            (Self::Nearest(mut records), Query::Packets) => {
                trace_packets_into(world, rays, &mut records);
                Self::Nearest(records)
            }
            (Self::Nearest(mut records), query) => {
                trace_rays_into(world, rays, query == Query::AnyHit, &mut records);
                Self::Nearest(records)
            }
            (Self::All(_), query) => Self::Nearest(trace_rays(world, rays, query == Query::AnyHit)),
        }
    }

    /// Stages the rows for `path` (see [`stage_rows`]), with the instance column appended
    /// when `instance_ids`.
    pub fn stage(
        &self,
        staged: &mut StagedOutputs,
        path: &Path,
        instance_ids: bool,
    ) -> Result<(), HitsError> {
        fn rows<R, const N: usize>(records: &[R], row: fn(&R) -> [f32; N]) -> Vec<[f32; N]> {
            records.iter().map(row).collect()
        }
        match (self, instance_ids) {
            (Self::Nearest(r), false) => stage_rows(staged, path, &rows(r, HitRecord::row)),
            (Self::Nearest(r), true) => {
                stage_rows(staged, path, &rows(r, HitRecord::row_with_instance))
            }
            (Self::All(r), false) => stage_rows(staged, path, &rows(r, AllHitRecord::row)),
            (Self::All(r), true) => {
                stage_rows(staged, path, &rows(r, AllHitRecord::row_with_instance))
            }
        }
    }
}
