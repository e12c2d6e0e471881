//! Shared helpers for the integration tests and the accelerator benchmark: a seeded RNG,
//! scene generators ([`scenes`]), ray generators ([`rays`]), model files and their renders
//! ([`files`], [`render`]) and the list of accelerator kinds.
//!
//! Everything is deterministic: the same seed gives the same scene and rays on every machine,
//! so a failure names a seed and a ray index that reproduce it.

// Each test crate (and the bench, which includes this file by path) uses a different subset.
#![allow(dead_code)]

pub mod cli;
pub mod exr;
pub mod files;
pub mod hostile;
pub mod rays;
pub mod render;
pub mod scenes;
pub mod simd;

use lumis_core::accel::{Accel, AccelKind, BuildOptions, Hit, TraversalStats};
use lumis_core::geometry::{Geometry, Precision, WatertightRay};
use lumis_core::math::{Aabb, Ray, Vec3};

/// Every accelerator kind the crate offers ([`AccelKind::ALL`], which the binary's unit tests
/// check against every `--accel` value), so a kind added later is tested without editing any
/// list here.
pub fn all_kinds() -> Vec<AccelKind> {
    AccelKind::ALL.to_vec()
}

/// A splitmix64 generator (Steele, Lea, Flood 2014): tiny, seedable, good enough for test data.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator with the given seed.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`: the top 24 bits, so every value is exactly representable.
    pub fn f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f32()
    }

    /// Uniform integer in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f32) -> bool {
        self.f32() < p
    }

    /// Uniform point in box `b`.
    pub fn in_box(&mut self, b: &Aabb) -> Vec3 {
        Vec3::new(
            self.range(b.min.x, b.max.x),
            self.range(b.min.y, b.max.y),
            self.range(b.min.z, b.max.z),
        )
    }

    /// Uniform direction on the unit sphere.
    pub fn unit_vector(&mut self) -> Vec3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f32::consts::TAU);
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}

/// The nearest hit of `ray` through `accel`, with the closure the renderer uses.
pub fn closest(accel: &Accel, geometry: &Geometry, ray: &Ray) -> Option<Hit> {
    let wr = WatertightRay::new(ray.dir);
    let hit = accel.intersect(ray, &mut TraversalStats::default(), |p, r| {
        geometry.intersect(p, r, &wr)
    });
    // The same query through the accelerator's own dispatch (packed leaves, when it has them)
    // must give the same answer, bit for bit.
    let packed = accel.intersect_geometry(
        geometry,
        Precision::Watertight,
        ray,
        &mut TraversalStats::default(),
    );
    assert!(
        same_hit(&hit, &packed),
        "packed leaves disagree with per-primitive tests: {hit:?} vs {packed:?} for {ray:?}"
    );
    hit
}

/// Bit-level equality of two answers (`PartialEq` on `f32` would call `0.0 == -0.0` equal).
pub fn same_hit(a: &Option<Hit>, b: &Option<Hit>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            a.prim == b.prim
                && a.hit.t.to_bits() == b.hit.t.to_bits()
                && a.hit.u.to_bits() == b.hit.u.to_bits()
                && a.hit.v.to_bits() == b.hit.v.to_bits()
        }
        _ => false,
    }
}

/// Whether anything blocks `ray` through `accel`.
pub fn occluded(accel: &Accel, geometry: &Geometry, ray: &Ray) -> bool {
    let wr = WatertightRay::new(ray.dir);
    let blocked = accel.occluded(ray, &mut TraversalStats::default(), |p, r| {
        geometry.intersect(p, r, &wr).is_some()
    });
    let packed = accel.occluded_geometry(
        geometry,
        Precision::Watertight,
        ray,
        &mut TraversalStats::default(),
    );
    assert_eq!(
        blocked, packed,
        "packed leaves disagree on occlusion for {ray:?}"
    );
    blocked
}

/// The brute-force reference over `geometry`.
pub fn brute(geometry: &Geometry) -> Accel {
    Accel::build_for(AccelKind::Brute, geometry, &BuildOptions::default())
}

/// Bounds of the scene, or a unit box for an empty one (rays need somewhere to start).
pub fn scene_box(geometry: &Geometry) -> Aabb {
    let b = geometry.bounds();
    if b.is_empty() {
        Aabb::new(Vec3::splat(-1.0), Vec3::ONE)
    } else {
        b
    }
}
