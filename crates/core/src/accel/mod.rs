//! Ray-query acceleration: a brute-force reference and bounding-volume hierarchies.
//!
//! Builders see only the primitives' bounding boxes; queries reach the primitives through a
//! closure, so accelerators know nothing of shapes or materials:
//! `accel.intersect(&ray, &mut stats, |prim, ray| geometry.intersect(prim, ray, &wr))`.
//! The one exception is an optimisation: [`Accel::build_for`] lets the wide hierarchy keep a
//! copy of the triangles in its leaf order ([`PackedLeaves`]), which the scene-level queries
//! ([`Accel::intersect_geometry`]) read instead of calling the closure per primitive.
//!
//! Every accelerator returns exactly the brute-force answer: the nearest hit, with exact-`t`
//! ties broken towards the lower primitive index.

mod all_hits;
mod batch_queries;
mod brute;
mod bsp;
mod build;
mod bvh;
mod exhaustive;
pub(crate) mod leaves;
mod one_instance;
mod packed;
mod query;
pub(crate) mod sah;
mod segments;
#[cfg(test)]
mod test_boxes;
mod wide;

pub use all_hits::{AllHit, AllHits, AllHitsScratch};
pub use bsp::SplitRule;
pub use bvh::{Bvh, Node};
// The frame lives with the geometry, whose instances frame rays too; named here as ever.
pub use crate::geometry::frame::{Framing, Moved, NEAR_FACTOR, RayFrame};
pub use query::Traced;
pub use segments::{PAPER_SEGMENT_MAX, SegmentParams};

pub use wide::{LEAF_ALIGN, PACKET, PADDING, SimdPath, Wide8, WideBvh, WideNode};

use std::sync::Arc;

use crate::geometry::{Geometry, PrimHit, Primitive};
use crate::math::{Aabb, Ray};
pub use packed::PackedLeaves;
pub(crate) use packed::{NO_SLOT, PackedContacts, PackedWatertight};

/// The bytes an accelerator holds, by part ([`Accel::memory`]): the scene's own vertex and
/// index arrays are not among them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AccelMemory {
    /// The nodes and whatever is kept per node beside them.
    pub nodes: usize,
    /// The primitive index of every leaf slot, padding included.
    pub leaf_order: usize,
    /// The triangles copied in leaf order ([`PackedLeaves`]).
    pub packed: usize,
}

impl AccelMemory {
    /// All parts together.
    pub fn total(&self) -> usize {
        self.nodes + self.leaf_order + self.packed
    }
}

/// Which acceleration structure to build.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AccelKind {
    /// Test every primitive: the reference all others are checked against.
    Brute,
    /// The paper's baseline: split at the spatial centre, axes cycling x, y, z.
    Bsp,
    /// The paper's BSMP: split at the median primitive centroid, axes cycling.
    Bsmp,
    /// Binned surface-area-heuristic BVH, collapsed to 8-wide SIMD nodes with packed leaves.
    Sah,
}

impl AccelKind {
    /// Every kind, for tests and benchmarks that cover them all.
    pub const ALL: [AccelKind; 4] = [
        AccelKind::Brute,
        AccelKind::Bsp,
        AccelKind::Bsmp,
        AccelKind::Sah,
    ];

    /// The leaf size each kind uses unless told otherwise: the paper's 20 for its partitions.
    pub fn default_leaf_size(self) -> usize {
        match self {
            AccelKind::Brute => 1,
            AccelKind::Bsp | AccelKind::Bsmp => 20,
            AccelKind::Sah => 4,
        }
    }

    /// The name used on the command line (`--accel`) and in Python (`accel=`).
    pub fn name(self) -> &'static str {
        match self {
            AccelKind::Brute => "brute",
            AccelKind::Bsp => "bsp",
            AccelKind::Bsmp => "bsmp",
            AccelKind::Sah => "sah",
        }
    }
}

impl std::str::FromStr for AccelKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        AccelKind::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| format!("unknown accel {s:?}; expected brute, bsp, bsmp or sah"))
    }
}

impl std::fmt::Display for AccelKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// How a hierarchy is walked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Traversal {
    /// Front to back with a shrinking `t_max` (any-hit: first blocker wins).
    Ordered,
    /// The paper's scale lights: segment marching (see [`SegmentParams`]).
    Segments(SegmentParams),
    /// The paper's own recursion: every crossed node, no order, no culling by the best hit
    /// (any-hit queries still stop at the first blocker).
    Exhaustive,
    /// Segment marching with the original's defect (returns the first segment's best hit even
    /// when a nearer one lies in a later segment): WRONG ANSWERS, for measuring only. Compiled
    /// only with the `paper-original-rule` feature, which `lumis-lab` turns on and the `lumis`
    /// command does not: the product's dispatch has no wrong arm.
    #[cfg(feature = "paper-original-rule")]
    SegmentsOriginalRule(SegmentParams),
}

/// Build parameters shared by the hierarchies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuildOptions {
    /// Largest number of primitives a leaf may hold when a split is possible.
    pub max_leaf_size: usize,
    /// How the SAH hierarchy is built (the paper's hierarchies ignore it).
    pub quality: BuildQuality,
}

impl Default for BuildOptions {
    fn default() -> Self {
        Self {
            max_leaf_size: 4,
            quality: BuildQuality::default(),
        }
    }
}

/// The SAH builder: every split priced over all primitives, or a faster build over Morton
/// clusters (see BENCHMARKS.md, "Build", for what each costs per build and per ray).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BuildQuality {
    /// Binned and swept SAH over all primitives at every level.
    #[default]
    Full,
    /// Morton-order clusters under a SAH top, the full builder inside each cluster.
    Fast,
}

/// Counters a traversal adds to; kept per thread and summed afterwards.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct TraversalStats {
    /// Hierarchy nodes whose box was tested.
    pub nodes_visited: u64,
    /// Ray/primitive tests.
    pub prim_tests: u64,
    /// Segments marched by the scale-lights traversal.
    pub segments: u64,
}

impl std::ops::AddAssign for TraversalStats {
    fn add_assign(&mut self, o: Self) {
        self.nodes_visited += o.nodes_visited;
        self.prim_tests += o.prim_tests;
        self.segments += o.segments;
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

    /// Takes `hit` on `prim` when it is nearer (or as near, on a lower index); says whether.
    #[inline(always)]
    pub fn offer(&mut self, prim: u32, hit: PrimHit) -> bool {
        let better = match self.best {
            None => true,
            Some(b) => hit.t < b.hit.t || (hit.t == b.hit.t && prim < b.prim),
        };
        if better {
            self.best = Some(Hit { prim, hit });
            self.ray.t_max = hit.t;
        }
        better
    }
}

/// A built acceleration structure over a fixed primitive list, with its traversal.
#[derive(Clone, Debug)]
pub struct Accel {
    kind: AccelKind,
    structure: Structure,
    traversal: Traversal,
    /// Where queries are traced from (every query goes through it: far origins are moved).
    frame: RayFrame,
    /// The triangles in the wide hierarchy's leaf order (see [`Accel::build_for`]).
    packed: Option<Arc<PackedLeaves>>,
    /// The scene is one instance, which queries ask at once (see `one_instance`).
    only_instance: Option<one_instance::OnlyInstance>,
}

#[derive(Clone, Debug)]
enum Structure {
    /// Every primitive, tested in index order.
    Brute(brute::Brute),
    /// A hierarchy in one flat node array.
    Bvh(Bvh),
    /// The SAH tree collapsed to 8-wide nodes for the ordered walk. The paper's traversals
    /// (segments, exhaustive) are defined on binary nodes: choosing one unfolds the wide tree
    /// back into the binary tree it came from ([`WideBvh::to_binary`]).
    Wide(Box<Wide8>),
}

impl Accel {
    /// Builds `kind` over primitives with the given bounds (index = primitive index), walked
    /// with the ordered traversal.
    pub fn build(kind: AccelKind, bounds: &[Aabb], opts: &BuildOptions) -> Self {
        Self::build_priced(kind, bounds, &[], opts)
    }

    /// [`Accel::build`] with the SAH told which primitives share a SIMD test
    /// ([`sah::build`]); the other builders ignore `slots`.
    fn build_priced(kind: AccelKind, bounds: &[Aabb], slots: &[u8], opts: &BuildOptions) -> Self {
        let structure = match kind {
            AccelKind::Brute => Structure::Brute(brute::Brute::new(bounds)),
            AccelKind::Bsp => Structure::Bvh(bsp::build(bounds, opts, SplitRule::SpatialCentre)),
            AccelKind::Bsmp => Structure::Bvh(bsp::build(bounds, opts, SplitRule::MedianCentroid)),
            AccelKind::Sah => {
                Structure::Wide(Box::new(Wide8::collapse(&sah::build(bounds, slots, opts))))
            }
        };
        let scene = bounds.iter().fold(Aabb::EMPTY, |b, p| b.union(*p));
        Self {
            kind,
            structure,
            traversal: Traversal::Ordered,
            frame: RayFrame::new(scene),
            packed: None,
            only_instance: None,
        }
    }

    /// Builds `kind` over the primitives of `geometry` and, for the wide hierarchy, copies the
    /// triangles into its leaf order ([`PackedLeaves`]) for the scene's watertight queries.
    pub fn build_for(kind: AccelKind, geometry: &Geometry, opts: &BuildOptions) -> Self {
        // Only triangles are packed four to a SIMD test.
        let slots: Vec<u8> = geometry
            .prims()
            .iter()
            .map(|p| match p {
                Primitive::Triangle { .. } => sah::SHARED_SLOTS,
                Primitive::Sphere { .. } | Primitive::Instance { .. } => sah::ALONE_SLOTS,
            })
            .collect();
        let mut accel = Self::build_priced(kind, &geometry.prim_bounds(), &slots, opts);
        if let Structure::Wide(w) = &accel.structure {
            accel.packed = Some(Arc::new(PackedLeaves::new(geometry, w.prim_order())));
        }
        accel.note_only_instance(geometry);
        accel
    }

    /// The packed triangles and the walk that reads them, when this accelerator has them and
    /// is walked in order (the paper's traversals run on the binary tree, in its own order).
    pub(crate) fn packed(&self) -> Option<(&Wide8, &PackedLeaves)> {
        match (&self.structure, &self.packed) {
            (Structure::Wide(w), Some(p)) => Some((w, p)),
            _ => None,
        }
    }

    /// The corners of the triangle at `slot` of the packed leaves (see [`Traced::slot`]):
    /// bit-identical copies of the mesh's, read from where the walk just was instead of through
    /// the mesh's index buffer (on the 1.1M-triangle bunny those reads took a quarter of a
    /// `lumis hits` query's time).
    pub fn packed_corners(&self, slot: u32) -> Option<[crate::math::Vec3; 3]> {
        self.packed.as_ref()?.corners(slot)
    }

    /// The packed leaves of each prototype of `geometry`, shared, in prototype order: where a
    /// hit inside an instance ([`Traced::slot`]) finds its triangle's corners, in object space.
    pub fn prototype_leaves(geometry: &Geometry) -> Vec<Option<Arc<PackedLeaves>>> {
        geometry
            .prototypes()
            .iter()
            .map(|p| p.hierarchy().downcast_ref::<Accel>()?.packed.clone())
            .collect()
    }

    /// Where this accelerator traces queries from: the scene's bounds and near region.
    pub fn frame(&self) -> &RayFrame {
        &self.frame
    }

    /// Bytes of the hierarchy and of the packed leaves, for the bytes-per-primitive figure.
    pub fn bytes(&self) -> usize {
        self.memory().total()
    }

    /// [`Accel::bytes`] by part.
    pub fn memory(&self) -> AccelMemory {
        let (nodes, leaf_order) = match &self.structure {
            Structure::Brute(_) => (0, 0),
            Structure::Bvh(b) => (std::mem::size_of_val(b.nodes()), 4 * b.prim_order().len()),
            Structure::Wide(w) => (w.node_bytes(), 4 * w.prim_order().len()),
        };
        AccelMemory {
            nodes,
            leaf_order,
            packed: self.packed.as_ref().map_or(0, |p| p.bytes()),
        }
    }

    /// The expected cost of a ray through the wide hierarchy (see [`WideBvh::sah_cost`]), to
    /// compare builders; `None` for the other structures.
    pub fn sah_cost(&self) -> Option<f64> {
        match &self.structure {
            Structure::Wide(w) => Some(w.sah_cost()),
            _ => None,
        }
    }

    /// This accelerator walked with `traversal` instead. Brute force has no nodes to march
    /// segments over, so it answers the same either way.
    pub fn with_traversal(mut self, traversal: Traversal) -> Self {
        self.traversal = traversal;
        if let (Structure::Wide(w), false) = (&self.structure, traversal == Traversal::Ordered) {
            self.structure = Structure::Bvh(w.to_binary());
            self.packed = None;
            self.only_instance = None;
        }
        self
    }

    /// What was built.
    pub fn kind(&self) -> AccelKind {
        self.kind
    }

    /// How it is walked.
    pub fn traversal(&self) -> Traversal {
        self.traversal
    }

    /// The hierarchy, unless this is brute force.
    pub fn bvh(&self) -> Option<&Bvh> {
        match &self.structure {
            Structure::Brute(_) => None,
            Structure::Bvh(b) => Some(b),
            Structure::Wide(_) => None,
        }
    }

    /// The wide hierarchy the ordered walk uses, when this kind has one.
    pub fn wide(&self) -> Option<&Wide8> {
        match &self.structure {
            Structure::Wide(w) => Some(w),
            _ => None,
        }
    }

    /// Number of hierarchy nodes (0 for brute force).
    pub fn node_count(&self) -> usize {
        match &self.structure {
            Structure::Brute(_) => 0,
            Structure::Bvh(b) => b.nodes().len(),
            Structure::Wide(w) => w.nodes().len(),
        }
    }
}
