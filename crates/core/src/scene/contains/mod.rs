//! Point containment: [`World::contains`], whether points lie inside the scene's solids.
//!
//! The rules (docs/hard-cases.md, "Point containment"):
//! - A point is inside the scene when it is inside any object. A point outside an object's
//!   bounds is outside it.
//! - A **closed** mesh ([`closed`]: every edge shared by an even number of faces, vertices at
//!   one position counted as one) answers exactly: a point on the surface (on a triangle with
//!   area, decided in exact arithmetic) is inside, the solid being a closed set; any other
//!   point is inside when the line through it along a fixed direction crosses the mesh an odd
//!   number of times ahead of it, the crossings counted by the all-hits rule and placed ahead
//!   or behind exactly ([`parity`]).
//! - A **sphere** holds the points of its closed ball, `|p - c| <= r` exactly.
//! - A mesh that is **not closed** (or is alpha-tested) answers by its generalized winding
//!   number ([`winding`]): inside when `|w| >= 1/2`, or when the point is on its surface
//!   (exactly, as above).
//! - An **instance** answers for its parts in the prototype's space: the point is mapped there
//!   by the inverse placement in `f64` and rounded to `f32` once, as the instance's rays are;
//!   the answer is then the exact one for that point (exact in world space where the mapping
//!   is, as for integer translations, axis permutations and power-of-two scales).
//!
//! Everything a query needs is built once per world, on the first query
//! ([`ContainmentIndex`]); queries share it read-only, so any number of threads can ask.

mod box_tree;
mod closed;
mod parity;
mod shape;
mod winding;

#[cfg(test)]
mod tests;

use rayon::prelude::*;

use self::box_tree::{BoxTree, holds};
use self::parity::LineHits;
use self::shape::{MeshShape, winding_inside};
use super::{Scene, World};
use crate::geometry::{Geometry, Instance, Primitive, ball_contains};
use crate::math::{Aabb, Vec3};

/// How an object answers containment queries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ContainmentMethod {
    /// Exactly: a closed mesh (even-odd rule, the surface inside) or a sphere.
    Exact,
    /// By the generalized winding number, thresholded at 1/2: a mesh that is not closed.
    WindingNumber,
}

/// The answer for one point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Containment {
    /// The point is inside some object (or on its surface).
    pub inside: bool,
    /// What decided it: `Exact` when an exact object holds the point, or when no object
    /// answering by winding number was asked (its bounds do not hold the point);
    /// `WindingNumber` otherwise.
    pub method: ContainmentMethod,
}

/// A query point outside the domain.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error("point {index}: [{:e}, {:e}, {:e}] is not finite; points must be finite", .point.x, .point.y, .point.z)]
pub struct PointError {
    /// Its index in the caller's list.
    pub index: usize,
    /// The point.
    pub point: Vec3,
}

/// Refuses the first point with a NaN or infinite coordinate.
pub fn check_points(points: &[Vec3]) -> Result<(), PointError> {
    match points.iter().position(|p| !p.is_finite()) {
        Some(index) => Err(PointError {
            index,
            point: points[index],
        }),
        None => Ok(()),
    }
}

/// What holds the point: a scene mesh, a sphere or an instance.
#[derive(Clone, Copy, Debug)]
enum Item {
    Mesh(u32),
    Sphere(u32),
    Instance(u32),
}

/// Everything containment queries need of a world, built once.
#[derive(Debug)]
pub(crate) struct ContainmentIndex {
    /// The scene's meshes, by mesh index.
    meshes: Vec<MeshShape>,
    /// Each prototype's meshes, by prototype and mesh index.
    prototypes: Vec<Vec<MeshShape>>,
    /// Meshes, spheres and instances, and their boxes.
    items: Vec<Item>,
    boxes: Vec<Aabb>,
    /// Over `boxes`.
    tree: BoxTree,
    /// How each object answers, by object id.
    methods: Vec<ContainmentMethod>,
}

impl ContainmentIndex {
    /// Prepares every mesh of `scene` (its meshes in parallel) and the hierarchy over objects.
    pub(crate) fn build(scene: &Scene) -> Self {
        let g = scene.geometry();
        let prepare = |g: &Geometry| -> Vec<MeshShape> {
            g.meshes().par_iter().map(MeshShape::build).collect()
        };
        let meshes = prepare(g);
        let prototypes: Vec<Vec<MeshShape>> = g
            .prototypes()
            .iter()
            .map(|p| prepare(p.geometry()))
            .collect();
        let mut items = Vec::new();
        let mut boxes = Vec::new();
        for (i, m) in meshes.iter().enumerate() {
            items.push(Item::Mesh(i as u32));
            boxes.push(m.bounds);
        }
        for (i, s) in g.spheres().iter().enumerate() {
            items.push(Item::Sphere(i as u32));
            boxes.push(s.bounds());
        }
        for (i, inst) in g.instances().iter().enumerate() {
            items.push(Item::Instance(i as u32));
            boxes.push(inst.bounds);
        }
        let tree = BoxTree::build(&boxes, 0..items.len() as u32);
        let methods = object_methods(scene, &meshes, &prototypes);
        Self {
            meshes,
            prototypes,
            items,
            boxes,
            tree,
            methods,
        }
    }

    /// Whether `p` is inside `world`'s solids (this index is `world`'s), and what decided it.
    fn classify(&self, world: &World, p: Vec3) -> Containment {
        let exact = |inside| Containment {
            inside,
            method: ContainmentMethod::Exact,
        };
        if !p.is_finite() {
            return exact(false);
        }
        let mut near = Vec::new();
        self.tree.for_each_near(p, |i| {
            if holds(&self.boxes[i as usize], p) {
                near.push(self.items[i as usize]);
            }
        });
        // Exact objects first, so a point they hold is reported as decided exactly.
        let mut line = None;
        if near
            .iter()
            .any(|&item| self.exact_holds(world, item, p, &mut line))
        {
            return exact(true);
        }
        let mut asked = false;
        let inside = near
            .iter()
            .any(|&item| self.winding_holds(world, item, p, &mut asked));
        Containment {
            inside,
            method: if asked {
                ContainmentMethod::WindingNumber
            } else {
                ContainmentMethod::Exact
            },
        }
    }

    /// True when an exact part of `item` holds `p`; `line` keeps the world line's hits once
    /// traced.
    fn exact_holds(&self, world: &World, item: Item, p: Vec3, line: &mut Option<LineHits>) -> bool {
        let g = world.scene().geometry();
        match item {
            Item::Sphere(s) => {
                let s = &g.spheres()[s as usize];
                ball_contains(s.center, s.radius, p)
            }
            Item::Mesh(m) => {
                let (shape, mesh) = (&self.meshes[m as usize], &g.meshes()[m as usize]);
                shape.closed
                    && (shape.on_surface(mesh, p)
                        || line
                            .get_or_insert_with(|| LineHits::of_world(world, p))
                            .odd_ahead(g, m, p))
            }
            Item::Instance(i) => {
                let inst = &g.instances()[i as usize];
                let Some(q) = object_point(inst, p) else {
                    return false;
                };
                let proto = &g.prototypes()[inst.prototype as usize];
                let pg = proto.geometry();
                let shapes = &self.prototypes[inst.prototype as usize];
                let spheres = pg.spheres().iter();
                if spheres
                    .filter(|s| holds(&s.bounds(), q))
                    .any(|s| ball_contains(s.center, s.radius, q))
                {
                    return true;
                }
                let precision = world.scene().settings().precision;
                let mut line = None;
                shapes.iter().enumerate().any(|(m, shape)| {
                    let mesh = &pg.meshes()[m];
                    shape.closed
                        && holds(&shape.bounds, q)
                        && (shape.on_surface(mesh, q)
                            || line
                                .get_or_insert_with(|| {
                                    LineHits::of_prototype(proto.as_ref(), precision, q)
                                })
                                .odd_ahead(pg, m as u32, q))
                })
            }
        }
    }

    /// True when a part of `item` that answers by winding number holds `p`; sets `asked` when
    /// `item` has such a part whose bounds hold `p`.
    fn winding_holds(&self, world: &World, item: Item, p: Vec3, asked: &mut bool) -> bool {
        let g = world.scene().geometry();
        let mut open_holds = |shape: &MeshShape, mesh, q: Vec3| {
            if shape.closed || !holds(&shape.bounds, q) {
                return false;
            }
            *asked = true;
            shape.on_surface(mesh, q) || shape.winding(mesh, q).is_some_and(winding_inside)
        };
        match item {
            Item::Sphere(_) => false,
            Item::Mesh(m) => open_holds(&self.meshes[m as usize], &g.meshes()[m as usize], p),
            Item::Instance(i) => {
                let inst = &g.instances()[i as usize];
                let Some(q) = object_point(inst, p) else {
                    return false;
                };
                let pg = g.prototypes()[inst.prototype as usize].geometry();
                let shapes = &self.prototypes[inst.prototype as usize];
                shapes
                    .iter()
                    .zip(pg.meshes())
                    .any(|(shape, mesh)| open_holds(shape, mesh, q))
            }
        }
    }
}

/// `p` in the object space of `inst`: mapped in `f64`, rounded to `f32` once (as the
/// instance's rays are); `None` when that is not finite.
fn object_point(inst: &Instance, p: Vec3) -> Option<Vec3> {
    let q = inst
        .placement
        .world_to_object()
        .transform_point3(p.as_dvec3())
        .as_vec3();
    q.is_finite().then_some(q)
}

/// How each object of `scene` answers: by winding number for a mesh that is not closed (a
/// placed one included), exactly otherwise.
fn object_methods(
    scene: &Scene,
    meshes: &[MeshShape],
    prototypes: &[Vec<MeshShape>],
) -> Vec<ContainmentMethod> {
    let mut methods = vec![ContainmentMethod::Exact; scene.objects().len()];
    let g = scene.geometry();
    let first_prims = |g: &Geometry| -> Vec<Option<u32>> {
        let mut first = vec![None; g.meshes().len()];
        for (i, p) in g.prims().iter().enumerate() {
            if let Primitive::Triangle { mesh, .. } = *p {
                first[mesh as usize].get_or_insert(i as u32);
            }
        }
        first
    };
    for (shape, first) in meshes.iter().zip(first_prims(g)) {
        if let (false, Some(prim)) = (shape.closed, first) {
            methods[scene.object_of(prim) as usize] = ContainmentMethod::WindingNumber;
        }
    }
    let proto_firsts: Vec<Vec<Option<u32>>> = g
        .prototypes()
        .iter()
        .map(|p| first_prims(p.geometry()))
        .collect();
    for (i, inst) in g.instances().iter().enumerate() {
        let proto = inst.prototype as usize;
        for (shape, first) in prototypes[proto].iter().zip(&proto_firsts[proto]) {
            if let (false, Some(inner)) = (shape.closed, *first) {
                methods[scene.instance_object(i as u32, inner) as usize] =
                    ContainmentMethod::WindingNumber;
            }
        }
    }
    methods
}

impl World {
    /// Whether each of `points` lies inside the scene's solids (the module docs state the
    /// rules; on a surface counts as inside), in parallel on the current rayon pool, in point
    /// order; the same answers for any thread count. Refuses the first non-finite point.
    pub fn contains(&self, points: &[Vec3]) -> Result<Vec<bool>, PointError> {
        Ok(self
            .containment(points)?
            .into_iter()
            .map(|c| c.inside)
            .collect())
    }

    /// [`World::contains`] with what decided each answer.
    pub fn containment(&self, points: &[Vec3]) -> Result<Vec<Containment>, PointError> {
        check_points(points)?;
        let index = self.containment_index();
        Ok(points
            .par_iter()
            .with_min_len(256)
            .map(|&p| index.classify(self, p))
            .collect())
    }

    /// Whether `p` lies inside the scene's solids, and what decided it (a non-finite point
    /// is outside). Safe to call from many threads at once.
    pub fn contains_point(&self, p: Vec3) -> Containment {
        self.containment_index().classify(self, p)
    }

    /// How each object answers containment queries, by object id.
    pub fn containment_methods(&self) -> &[ContainmentMethod] {
        &self.containment_index().methods
    }
}
