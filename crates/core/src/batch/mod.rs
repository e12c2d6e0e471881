//! Batch ray queries: many rays through one [`World`] in parallel, one answer per ray in input
//! order. `lumis hits` (rays from an `.npy` file) and the Python package (rays read in place
//! from numpy arrays) both call [`trace_rays`], so they give the same answers bit for bit.
//!
//! Rays are world space, `origin + t dir` with `t` in `(t_min, t_max]`, inside the query domain
//! ([`crate::scene::domain`]; check them with [`check_rays`]). The answers:
//! - [`HitRecord`]: `t`, primitive id, object id, barycentric `u`, `v` (weights of the
//!   triangle's second and third vertex; 0 for spheres), unit geometric normal (outward for
//!   spheres, by winding for triangles), primitive kind. Its [`HitRecord::row`] is the
//!   `(N, 9)` float32 row `lumis hits` writes: a miss is `t = +inf`, ids and kind `-1`, the
//!   rest 0. [`HitRecord::row_with_instance`] appends a tenth column, the instance id (`-1`
//!   outside any instance; then `prim` is the prototype's primitive, as Embree's `primID`
//!   with its `instID`). Any-hit queries report the `t` of whichever blocker the traversal met first (not
//!   necessarily the nearest; `+inf` when unoccluded), no ids, no kind.
//! - [`AllHitRecord`]: every hit along a ray ([`World::all_hits`]: each surface crossing
//!   counted once, plus the grazes), with its ray's index and a graze flag; its
//!   [`AllHitRecord::row`] is the `(M, 11)` row of `lumis hits --all`: ray index, the nine
//!   hit columns, graze (1 or 0). The records of ray 0 come first, then ray 1's, each ray's
//!   sorted by `t` (ties by primitive id); a ray without hits has none.
//!   [`AllHitRecord::row_with_instance`] appends the instance id as a twelfth column.
//! - spawn origins `(N, 6)`, row `i` for ray `i`: where a secondary ray leaving the hit would
//!   start under the scene's `offset` rule, on the side the ray came from (xyz, what shadow and
//!   reflection rays use) and on the far side (xyz, what refraction uses); `+inf` for misses.
//! - triangles `(M, 10)`: primitive id, then the three world-space vertices.
//! - spheres `(K, 5)`: primitive id, world-space centre xyz, radius.
//!
//! The float rows store ids as float32, exact up to 2^24; [`HitRecord`] holds them exactly.

mod records;

use rayon::prelude::*;

pub use records::{AllHitRecord, HitRecord, PrimKind};

use crate::accel::{AllHit, Hit, PACKET, Traced, TraversalStats};
use crate::geometry::Primitive;
use crate::math::{Ray, Vec3};
use crate::scene::domain::{RayError, check_ray};
use crate::scene::{AllHitsBuffers, Scene, World};

/// Floats per ray row: origin xyz, direction xyz, `t_min`, `t_max`.
pub const RAY_COLUMNS: usize = 8;
/// Floats per hit row.
pub const HIT_COLUMNS: usize = 9;
/// Floats per all-hits row: ray index, the hit columns, graze.
pub const ALL_HIT_COLUMNS: usize = HIT_COLUMNS + 2;
/// Floats per hit row with the instance column ([`HitRecord::row_with_instance`]).
pub const HIT_INSTANCE_COLUMNS: usize = HIT_COLUMNS + 1;
/// Floats per all-hits row with the instance column ([`AllHitRecord::row_with_instance`]).
pub const ALL_HIT_INSTANCE_COLUMNS: usize = ALL_HIT_COLUMNS + 1;
/// Floats per triangle row.
pub const TRIANGLE_COLUMNS: usize = 10;
/// Floats per sphere row.
pub const SPHERE_COLUMNS: usize = 5;
/// Floats per spawn row.
pub const SPAWN_COLUMNS: usize = 6;

/// One ray as a row: origin xyz, direction xyz, `t_min`, `t_max`.
pub type RayRow = [f32; RAY_COLUMNS];
/// One hit as `lumis hits` writes it (see the module docs).
pub type HitRow = [f32; HIT_COLUMNS];

/// Rays per parallel work item: large enough to amortise scheduling, small enough to balance.
const CHUNK: usize = 1024;

/// Nearest-hit rays walked at once on each thread ([`World::trace_each`]): while one ray
/// waits for the nodes it is about to visit, the others take their steps. Time per ray against
/// one at a time on the 1.1M-triangle bunny (a hierarchy far larger than the caches):
/// incoherent -37 to -52%, camera -27 to -45% (one at a time varies with the other core's
/// memory traffic, this does not); on the 69k bunny (in the L3) -3 to -5%; misses -5%. 12 was
/// ~5% faster than 8 on the large bunny, 16 no faster than 12 (BENCHMARKS.md, Phase 14).
pub const IN_FLIGHT: usize = 12;

/// Rays addressed by index, read where they are (rows of a file, columns of numpy arrays).
pub trait RayBatch: Sync {
    /// How many rays.
    fn len(&self) -> usize;
    /// Whether there are none.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Ray `i`, `i < len()`.
    fn ray(&self, i: usize) -> Ray;
}

impl RayBatch for [RayRow] {
    fn len(&self) -> usize {
        <[RayRow]>::len(self)
    }

    fn ray(&self, i: usize) -> Ray {
        let r = &self[i];
        Ray {
            origin: Vec3::new(r[0], r[1], r[2]),
            dir: Vec3::new(r[3], r[4], r[5]),
            t_min: r[6],
            t_max: r[7],
        }
    }
}

/// The first ray of `rays` outside the query domain, with its index and why.
pub fn check_rays<B: RayBatch + ?Sized>(rays: &B) -> Result<(), (usize, RayError)> {
    // In parallel, reporting the smallest bad index as a serial scan would.
    (0..rays.len())
        .into_par_iter()
        .find_map_first(|i| {
            let r = rays.ray(i);
            check_ray(r.origin, r.dir, r.t_min, r.t_max)
                .err()
                .map(|e| (i, e))
        })
        .map_or(Ok(()), Err)
}

/// Every hit along every ray ([`World::all_hits`]) in parallel on the current rayon pool, in
/// ray order (see the module docs). Rays must be inside the domain ([`check_rays`]); the
/// result does not depend on the thread count.
pub fn trace_all_hits<B: RayBatch + ?Sized>(world: &World, rays: &B) -> Vec<AllHitRecord> {
    trace_all_hits_parts(world, rays).concat()
}

/// [`trace_all_hits`] in parts, in ray order (concatenated, they are its answer; how the rays
/// are split depends on the threads): for callers that copy the records into their own layout
/// anyway, which then skip the concatenation, whose fresh memory cost more page faults than
/// copying (Python's columns).
pub fn trace_all_hits_parts<B: RayBatch + ?Sized>(
    world: &World,
    rays: &B,
) -> Vec<Vec<AllHitRecord>> {
    // Each split of the rays appends to one vector, with one set of buffers reused from ray
    // to ray: a vector per ray or per small chunk cost its growth and its page faults.
    (0..rays.len())
        .into_par_iter()
        .with_min_len(CHUNK)
        .fold(
            || {
                (
                    TraversalStats::default(),
                    AllHitsBuffers::default(),
                    Vec::new(),
                )
            },
            |(mut stats, mut buffers, mut records), i| {
                if let Some((traced, hits)) =
                    world.all_hits_found(&rays.ray(i), &mut stats, &mut buffers)
                {
                    records.extend(hits.iter().map(|h| AllHitRecord {
                        ray: i,
                        hit: all_hit_record(world, &traced, h),
                        graze: h.graze,
                    }));
                }
                (stats, buffers, records)
            },
        )
        .map(|(_, _, records)| records)
        .filter(|records| !records.is_empty())
        .collect()
}

/// The record of one hit of an all-hits query found on `traced` (the fields of
/// [`World::all_hits`]'s [`crate::scene::SurfaceHit`], as [`nearest_record`] reads them).
#[inline]
fn all_hit_record(world: &World, traced: &Ray, h: &AllHit) -> HitRecord {
    let scene = world.scene();
    let g = scene.geometry();
    let (prim, inner) = (h.prim, h.hit.inner);
    let instance = g.instance_of(prim);
    HitRecord {
        t: h.t,
        // An instance's hit names the prototype's primitive, as Embree's `primID` does.
        prim: Some(if instance.is_some() { inner } else { prim }),
        object: Some(match instance {
            Some(instance) => scene.instance_object(instance, inner),
            None => scene.object_of(prim),
        }),
        u: h.hit.u,
        v: h.hit.v,
        normal: world.all_hit_normal(traced, h),
        // A hit from the packed leaves is a triangle; only others read the primitive list.
        kind: Some(match h.slot {
            Some(_) => PrimKind::Triangle,
            None => g.leaf_primitive(prim, inner).into(),
        }),
        instance,
    }
}

/// Traces every ray through `world` in parallel on the current rayon pool; record `i` answers
/// ray `i`. With `any_hit`, only whether something blocks the ray, as the distance of the
/// first blocker met. Rays must be inside the domain ([`check_rays`]). The result does not
/// depend on the thread count. Primitives are intersected with the scene's `precision`.
pub fn trace_rays<B: RayBatch + ?Sized>(world: &World, rays: &B, any_hit: bool) -> Vec<HitRecord> {
    let mut records = Vec::new();
    trace_rays_into(world, rays, any_hit, &mut records);
    records
}

/// [`trace_rays`] into `records`, replacing what it held and reusing its allocation: a caller
/// tracing batch after batch (or timing repeats) pays for the memory once, not its page faults
/// on every batch.
pub fn trace_rays_into<B: RayBatch + ?Sized>(
    world: &World,
    rays: &B,
    any_hit: bool,
    records: &mut Vec<HitRecord>,
) {
    if any_hit {
        return trace_all(
            rays,
            |ray, stats| blocker_record(world, ray, stats),
            records,
        );
    }
    trace_nearest_into::<IN_FLIGHT, B>(world, rays, records)
}

/// [`trace_rays_into`] of nearest hits with up to `K` rays walked at once on each thread
/// ([`World::trace_each`]; `K = 1`: one at a time, as a render traces). The records are the
/// same for every `K`; public so tests and benchmarks can compare them.
pub fn trace_nearest_into<const K: usize, B: RayBatch + ?Sized>(
    world: &World,
    rays: &B,
    records: &mut Vec<HitRecord>,
) {
    records.clear();
    records.resize(rays.len(), HitRecord::MISS);
    records.par_chunks_mut(CHUNK).enumerate().for_each_init(
        TraversalStats::default,
        |stats, (c, out)| {
            let first = c * CHUNK;
            let mut next = 0..out.len();
            world.trace_each::<K, usize>(
                stats,
                || next.next().map(|i| (i, rays.ray(first + i))),
                |i, traced| out[i] = nearest_record(world, traced),
            );
        },
    );
}

/// [`trace_rays_into`] of nearest hits, with consecutive groups of [`PACKET`] rays walked
/// together as packets where they can be (one origin, one direction sign per axis: a pinhole
/// camera's tiles, as the renderer traces a pixel's samples; other groups go one ray at a
/// time). The records are the same bit for bit; only the time differs.
pub fn trace_packets_into<B: RayBatch + ?Sized>(
    world: &World,
    rays: &B,
    records: &mut Vec<HitRecord>,
) {
    records.clear();
    records.resize(rays.len(), HitRecord::MISS);
    records
        .par_chunks_mut(PACKET)
        .with_min_len(CHUNK / PACKET)
        .enumerate()
        .for_each_init(TraversalStats::default, |stats, (k, out)| {
            let packet: [Ray; PACKET] =
                std::array::from_fn(|i| rays.ray((k * PACKET + i).min(rays.len() - 1)));
            let packet = &packet[..out.len()];
            let mut traced = [None; PACKET];
            if world.trace_packet(packet, stats, &mut traced) {
                for (o, t) in out.iter_mut().zip(traced) {
                    *o = nearest_record(world, t);
                }
            } else {
                for (o, ray) in out.iter_mut().zip(packet) {
                    *o = nearest_record(world, world.trace(ray, stats));
                }
            }
        });
}

/// For every ray, the spawn origins of its hit (see the module docs); rays that miss get `inf`.
pub fn spawn_rows<B: RayBatch + ?Sized>(world: &World, rays: &B) -> Vec<[f32; SPAWN_COLUMNS]> {
    let offset = world.scene().settings().offset;
    let mut rows = Vec::new();
    trace_all(
        rays,
        |ray, stats| match world.intersect(ray, stats) {
            None => [f32::INFINITY; SPAWN_COLUMNS],
            Some(hit) => {
                let back = hit.surface.spawn_origin(-ray.dir, offset);
                let through = hit.surface.spawn_origin(ray.dir, offset);
                [back.x, back.y, back.z, through.x, through.y, through.z]
            }
        },
        &mut rows,
    );
    rows
}

/// Runs `f` over every ray in parallel chunks into `out` (replacing its contents, keeping its
/// allocation when large enough), in the input order. The records are written straight into
/// the one result vector (rayon's indexed collect), not gathered per chunk and copied: on 200k
/// rays that missed, the copy and its page faults took longer than the queries.
fn trace_all<B: RayBatch + ?Sized, T: Send>(
    rays: &B,
    f: impl Fn(&Ray, &mut TraversalStats) -> T + Sync,
    out: &mut Vec<T>,
) {
    (0..rays.len())
        .into_par_iter()
        .with_min_len(CHUNK)
        .map_init(TraversalStats::default, |stats, i| f(&rays.ray(i), stats))
        .collect_into_vec(out);
}

/// The record of an any-hit query of `ray`: only the distance of the blocker the traversal
/// stopped at.
fn blocker_record(world: &World, ray: &Ray, stats: &mut TraversalStats) -> HitRecord {
    match world.first_blocker(ray, stats) {
        Some(t) => HitRecord {
            t,
            ..HitRecord::MISS
        },
        None => HitRecord::MISS,
    }
}

/// The record of a nearest-hit query answered by the scene's own query ([`World::trace`]).
fn nearest_record(world: &World, traced: Option<Traced>) -> HitRecord {
    let scene = world.scene();
    let g = scene.geometry();
    let Some(traced) = traced else {
        return HitRecord::MISS;
    };
    // The normal on the ray the hit was found on (a far ray's was moved near the scene).
    let Hit { prim, hit } = traced.hit;
    let instance = g.instance_of(prim);
    HitRecord {
        t: traced.t,
        // An instance's hit names the prototype's primitive, as Embree's `primID` does.
        prim: Some(if instance.is_some() { hit.inner } else { prim }),
        object: Some(match instance {
            Some(instance) => scene.instance_object(instance, hit.inner),
            None => scene.object_of(prim),
        }),
        u: hit.u,
        v: hit.v,
        normal: world.geometric_normal_in(&traced, instance),
        // A hit from the packed leaves is a triangle; only others read the primitive list.
        kind: Some(match traced.slot {
            Some(_) => PrimKind::Triangle,
            None => g.leaf_primitive(prim, hit.inner).into(),
        }),
        instance,
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
            Primitive::Sphere { .. } | Primitive::Instance { .. } => None,
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
            Primitive::Triangle { .. } | Primitive::Instance { .. } => None,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_rays_names_the_first_bad_ray() {
        let good = [0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, f32::INFINITY];
        let mut bad = good;
        bad[3..6].fill(0.0);
        let rays = [good, good, bad, bad];
        assert_eq!(check_rays(&rays[..2]), Ok(()));
        assert!(matches!(
            check_rays(&rays[..]),
            Err((2, RayError::Direction(_)))
        ));
    }
}
