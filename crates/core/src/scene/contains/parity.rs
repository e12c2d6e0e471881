//! The even-odd answer for closed meshes: the crossings of one line through the query point,
//! as the all-hits query counts them (each crossing of an edge or a vertex once, touches that
//! do not cross flagged as grazes: docs/hard-cases.md, "All hits along a ray"), of which those
//! ahead of the point are counted.
//!
//! The whole line is traced (`t` over `[-inf, inf]`), and whether a crossing lies ahead is
//! decided exactly from the triangle it reports: the line meets the triangle's plane at
//! `t = n . (a - p) / n . d`, whose sign is that of two exact determinants. The reported `t`
//! is the plane distance rounded to `f32`, so a crossing a tiny distance ahead can read 0 or
//! even a tiny negative number; its sign is not used. The point must not lie on the surface
//! (the caller tests that first): then no crossing is at `t = 0`, and no triangle the line
//! touches has the point in its plane (a line in a triangle's plane never touches it).

use crate::geometry::{Geometry, Precision, PrimHit, Primitive, normal_dot_sign, orient3d};
use crate::math::{Ray, Vec3};

/// The direction of every containment line: fixed, so answers are reproducible, with no two
/// components in a simple ratio, so lattice meshes are rarely met at an edge (where the rule
/// is exact all the same, only slower).
pub(super) const DIRECTION: Vec3 = Vec3::new(0.754_877_7, 0.569_840_3, 0.324_718_1);

/// The line through `p` along [`DIRECTION`], every `t`.
pub(super) fn line(p: Vec3) -> Ray {
    Ray {
        origin: p,
        dir: DIRECTION,
        t_min: f32::NEG_INFINITY,
        t_max: f32::INFINITY,
    }
}

/// True when the line from `p` along [`DIRECTION`] meets the plane of triangle `corners`
/// ahead of `p` (`t > 0`), exactly; false on the plane.
pub(super) fn ahead(p: Vec3, [a, b, c]: [Vec3; 3]) -> bool {
    let side = orient3d(a, b, c, p);
    side.is_ne() && side == normal_dot_sign(a, b, c, DIRECTION)
}

/// The crossings of [`line`]`(p)` found by an all-hits query: the primitive of each (in the
/// geometry the query ran on) and whether it is a graze.
pub(super) struct LineHits {
    hits: Vec<(u32, bool)>,
}

impl LineHits {
    /// The line's hits in a world's geometry (`world` traced it).
    pub fn of_world(world: &super::World, p: Vec3) -> Self {
        let scene = world.scene();
        let found = world.accel().all_hits_geometry(
            scene.geometry(),
            scene.settings().precision,
            &line(p),
            &mut Default::default(),
        );
        Self {
            hits: found.hits.iter().map(|h| (h.prim, h.graze)).collect(),
        }
    }

    /// The line's hits in a prototype's geometry (its own all-hits query in object space):
    /// [`PrimHit::inner`] is the prototype's primitive.
    pub fn of_prototype(
        proto: &dyn crate::geometry::PrototypeQueries,
        precision: Precision,
        q: Vec3,
    ) -> Self {
        let found: Vec<(PrimHit, bool)> = proto.all_hits(&line(q), precision);
        Self {
            hits: found.iter().map(|(h, graze)| (h.inner, *graze)).collect(),
        }
    }

    /// True when an odd number of the crossings of mesh `mesh` of `g` lie ahead of `p` on the
    /// line: `p` is inside that mesh, if it is closed and `p` is not on it.
    pub fn odd_ahead(&self, g: &Geometry, mesh: u32, p: Vec3) -> bool {
        let mut odd = false;
        for &(prim, graze) in &self.hits {
            if graze {
                continue;
            }
            if let Primitive::Triangle { mesh: m, tri } = g.prims()[prim as usize]
                && m == mesh
                && ahead(p, g.meshes()[m as usize].corners(tri))
            {
                odd = !odd;
            }
        }
        odd
    }
}
