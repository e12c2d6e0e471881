//! Ray-query acceleration: a brute-force reference and bounding-volume hierarchies.
//!
//! Builders see only the primitives' bounding boxes; queries reach the primitives through a
//! closure, so accelerators know nothing of shapes or materials:
//! `accel.intersect(&ray, &mut stats, |prim, ray| geometry.intersect(prim, ray, &wr))`.
//!
//! Every accelerator returns exactly the brute-force answer: the nearest hit, with exact-`t`
//! ties broken towards the lower primitive index.

mod brute;
mod bvh;
mod sah;

pub use bvh::{Bvh, Node};

use crate::geometry::PrimHit;
use crate::math::{Aabb, Ray};

/// Which acceleration structure to build.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AccelKind {
    /// Test every primitive: the reference all others are checked against.
    Brute,
    /// Binned surface-area-heuristic BVH.
    Sah,
}

/// Build parameters shared by the hierarchies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuildOptions {
    /// Largest number of primitives a leaf may hold when a split is possible.
    pub max_leaf_size: usize,
}

impl Default for BuildOptions {
    fn default() -> Self {
        Self { max_leaf_size: 4 }
    }
}

/// Counters a traversal adds to; kept per thread and summed afterwards.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraversalStats {
    /// Hierarchy nodes whose box was tested.
    pub nodes_visited: u64,
    /// Ray/primitive tests.
    pub prim_tests: u64,
}

impl std::ops::AddAssign for TraversalStats {
    fn add_assign(&mut self, o: Self) {
        self.nodes_visited += o.nodes_visited;
        self.prim_tests += o.prim_tests;
    }
}

/// The nearest hit found by a query: primitive index plus the primitive's own hit record.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Index into the primitive list the accelerator was built over.
    pub prim: u32,
    /// Distance and barycentrics.
    pub hit: PrimHit,
}

/// Keeps the best hit so far and shrinks the ray to it. Equal `t` goes to the lower index, so
/// the answer does not depend on the order primitives are visited in.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Closest {
    pub ray: Ray,
    pub best: Option<Hit>,
}

impl Closest {
    pub fn new(ray: &Ray) -> Self {
        Self {
            ray: *ray,
            best: None,
        }
    }

    #[inline(always)]
    pub fn offer(&mut self, prim: u32, hit: PrimHit) {
        let better = match self.best {
            None => true,
            Some(b) => hit.t < b.hit.t || (hit.t == b.hit.t && prim < b.prim),
        };
        if better {
            self.best = Some(Hit { prim, hit });
            self.ray.t_max = hit.t;
        }
    }
}

/// A built acceleration structure over a fixed primitive list.
#[derive(Clone, Debug)]
pub enum Accel {
    /// Every primitive, tested in index order.
    Brute(brute::Brute),
    /// A hierarchy in one flat node array.
    Bvh(Bvh),
}

impl Accel {
    /// Builds `kind` over primitives with the given bounds (index = primitive index).
    pub fn build(kind: AccelKind, bounds: &[Aabb], opts: &BuildOptions) -> Self {
        match kind {
            AccelKind::Brute => Accel::Brute(brute::Brute::new(bounds)),
            AccelKind::Sah => Accel::Bvh(sah::build(bounds, opts)),
        }
    }

    /// The nearest hit of `ray` in `(t_min, t_max]`; `test(prim, ray)` intersects one primitive
    /// with a ray whose `t_max` has been shrunk to the best hit so far.
    #[inline]
    pub fn intersect<F>(&self, ray: &Ray, stats: &mut TraversalStats, test: F) -> Option<Hit>
    where
        F: FnMut(u32, &Ray) -> Option<PrimHit>,
    {
        match self {
            Accel::Brute(b) => b.intersect(ray, stats, test),
            Accel::Bvh(b) => b.intersect(ray, stats, test),
        }
    }

    /// True when anything blocks `ray` in `(t_min, t_max]`; stops at the first hit found.
    #[inline]
    pub fn occluded<F>(&self, ray: &Ray, stats: &mut TraversalStats, test: F) -> bool
    where
        F: FnMut(u32, &Ray) -> bool,
    {
        match self {
            Accel::Brute(b) => b.occluded(ray, stats, test),
            Accel::Bvh(b) => b.occluded(ray, stats, test),
        }
    }

    /// Number of hierarchy nodes (0 for brute force).
    pub fn node_count(&self) -> usize {
        match self {
            Accel::Brute(_) => 0,
            Accel::Bvh(b) => b.nodes().len(),
        }
    }
}
