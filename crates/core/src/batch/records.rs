//! The answers of batch queries and their float rows (see the module docs of [`super`]).

use super::{ALL_HIT_COLUMNS, ALL_HIT_INSTANCE_COLUMNS, HIT_COLUMNS, HIT_INSTANCE_COLUMNS, HitRow};
use crate::geometry::Primitive;
use crate::math::Vec3;

/// Which primitive a hit is on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrimKind {
    /// An analytic sphere (kind 0 in the rows).
    Sphere = 0,
    /// A mesh triangle (kind 1 in the rows).
    Triangle = 1,
}

impl From<Primitive> for PrimKind {
    fn from(p: Primitive) -> Self {
        match p {
            Primitive::Sphere { .. } => Self::Sphere,
            Primitive::Triangle { .. } => Self::Triangle,
            // Callers pass the primitive at the bottom of a hit (`Geometry::leaf_primitive`).
            Primitive::Instance { .. } => Self::Triangle,
        }
    }
}

/// One ray's answer (see the module docs): the nearest hit, an any-hit blocker's distance, or
/// a miss.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HitRecord {
    /// Distance along the caller's ray; `+inf` for a miss.
    pub t: f32,
    /// Primitive id; `None` for misses and any-hit answers.
    pub prim: Option<u32>,
    /// Object id (the scene's object list); `None` for misses and any-hit answers.
    pub object: Option<u32>,
    /// Barycentric weight of the triangle's second vertex (0 for spheres and misses).
    pub u: f32,
    /// Barycentric weight of the triangle's third vertex (0 for spheres and misses).
    pub v: f32,
    /// Unit geometric normal: outward for spheres, by winding for triangles; 0 for misses.
    pub normal: Vec3,
    /// The primitive's kind; `None` for misses and any-hit answers.
    pub kind: Option<PrimKind>,
    /// The instance hit (the scene's instance list), when the primitive is a prototype's;
    /// `prim` is then the prototype's primitive.
    pub instance: Option<u32>,
}

impl HitRecord {
    /// No hit.
    pub const MISS: Self = Self {
        t: f32::INFINITY,
        prim: None,
        object: None,
        u: 0.0,
        v: 0.0,
        normal: Vec3::ZERO,
        kind: None,
        instance: None,
    };

    /// The `lumis hits` row: `t`, prim id, object id, `u`, `v`, normal xyz, kind; `-1` for
    /// what is absent (ids as float32, exact up to 2^24).
    pub fn row(&self) -> HitRow {
        let id = |i: Option<u32>| i.map_or(-1.0, |i| i as f32);
        let n = self.normal;
        [
            self.t,
            id(self.prim),
            id(self.object),
            self.u,
            self.v,
            n.x,
            n.y,
            n.z,
            self.kind.map_or(-1.0, |k| k as u8 as f32),
        ]
    }

    /// [`Self::row`] with one more column at the end, the instance id (`-1` for a hit outside
    /// any instance, a miss or an any-hit answer): appended, so that a reader of the nine
    /// columns finds them where they were (`lumis hits --instance-ids`).
    pub fn row_with_instance(&self) -> [f32; HIT_INSTANCE_COLUMNS] {
        let mut row = [0.0; HIT_INSTANCE_COLUMNS];
        row[..HIT_COLUMNS].copy_from_slice(&self.row());
        row[HIT_COLUMNS] = self.instance.map_or(-1.0, |i| i as f32);
        row
    }
}

/// One hit of an all-hits query: the ray it belongs to, the hit, and whether it is a graze.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AllHitRecord {
    /// Index of the ray in the batch.
    pub ray: usize,
    /// The hit (always with ids and kind).
    pub hit: HitRecord,
    /// A touch that does not cross the surface (a silhouette edge or vertex, a tangent
    /// sphere); false for a crossing.
    pub graze: bool,
}

impl AllHitRecord {
    /// The `lumis hits --all` row: ray index, the [`HitRecord::row`] columns, graze (1 or 0);
    /// the index as float32, exact up to 2^24.
    pub fn row(&self) -> [f32; ALL_HIT_COLUMNS] {
        let mut row = [0.0; ALL_HIT_COLUMNS];
        row[0] = self.ray as f32;
        row[1..=HIT_COLUMNS].copy_from_slice(&self.hit.row());
        row[HIT_COLUMNS + 1] = if self.graze { 1.0 } else { 0.0 };
        row
    }

    /// [`Self::row`] with the instance id appended after the graze flag (`-1` outside any
    /// instance; `lumis hits --all --instance-ids`), every other column where it was.
    pub fn row_with_instance(&self) -> [f32; ALL_HIT_INSTANCE_COLUMNS] {
        let mut row = [0.0; ALL_HIT_INSTANCE_COLUMNS];
        row[..ALL_HIT_COLUMNS].copy_from_slice(&self.row());
        row[ALL_HIT_COLUMNS] = self.hit.instance.map_or(-1.0, |i| i as f32);
        row
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_mark_what_is_absent_with_minus_one() {
        assert_eq!(
            HitRecord::MISS.row(),
            [f32::INFINITY, -1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0]
        );
        let hit = HitRecord {
            t: 2.5,
            prim: Some(7),
            object: Some(1),
            u: 0.25,
            v: 0.5,
            normal: Vec3::new(0.0, 0.0, 1.0),
            kind: Some(PrimKind::Triangle),
            instance: None,
        };
        assert_eq!(hit.row(), [2.5, 7.0, 1.0, 0.25, 0.5, 0.0, 0.0, 1.0, 1.0]);
        assert_eq!(hit.row_with_instance()[..HIT_COLUMNS], hit.row());
        assert_eq!(hit.row_with_instance()[HIT_COLUMNS], -1.0);
        assert_eq!(HitRecord::MISS.row_with_instance()[HIT_COLUMNS], -1.0);
        let placed = HitRecord {
            instance: Some(5),
            ..hit
        };
        assert_eq!(placed.row(), hit.row());
        assert_eq!(placed.row_with_instance()[HIT_COLUMNS], 5.0);
        let all = AllHitRecord {
            ray: 3,
            hit: placed,
            graze: true,
        };
        let row = all.row_with_instance();
        assert_eq!(row[..ALL_HIT_COLUMNS], all.row());
        assert_eq!(row[ALL_HIT_COLUMNS], 5.0);
    }
}
