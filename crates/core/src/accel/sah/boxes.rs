//! The builder's boxes: a primitive's or a node's box with its maximum negated, so that the
//! union of two boxes is one minimum over all six planes (one SIMD instruction on eight lanes),
//! and the bounds of a node's centroids.

use crate::math::{Aabb, Vec3, Vec3A, Vec4};

/// A box as `(min, -max)`. The empty box is `+inf` everywhere.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub(super) struct Box3 {
    pub min: Vec3A,
    pub neg_max: Vec3A,
}

impl Box3 {
    pub const EMPTY: Self = Self {
        min: Vec3A::INFINITY,
        neg_max: Vec3A::INFINITY,
    };

    #[inline(always)]
    pub fn union(self, o: Self) -> Self {
        Self {
            min: self.min.min(o.min),
            neg_max: self.neg_max.min(o.neg_max),
        }
    }

    /// Half the surface area (the factor 2 cancels in the cost ratio); 0 when empty. The
    /// extent `-(-max + min)` rounds exactly as `max - min` does (rounding is symmetric).
    #[inline(always)]
    pub fn half_area(self) -> f32 {
        let e = (-(self.neg_max + self.min)).max(Vec3A::ZERO);
        e.x * e.y + e.y * e.z + e.z * e.x
    }

    pub fn aabb(self) -> Aabb {
        Aabb {
            min: Vec3::from(self.min),
            max: -Vec3::from(self.neg_max),
        }
    }
}

/// One primitive as the builder reads it: its box laid out as a [`Box3`] (one 32-byte load),
/// with the group lanes its test fills (see [`super::SHARED_SLOTS`]) in the spare lane.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub(super) struct Ref {
    /// `w`: the primitive's slots, as a float.
    min: Vec4,
    neg_max: Vec4,
}

impl Ref {
    /// The empty box, no slots.
    pub const EMPTY: Self = Self {
        min: Vec4::new(f32::INFINITY, f32::INFINITY, f32::INFINITY, 0.0),
        neg_max: Vec4::new(f32::INFINITY, f32::INFINITY, f32::INFINITY, 0.0),
    };

    pub fn new(b: &Aabb, slots: u8) -> Self {
        Self {
            min: b.min.extend(slots as f32),
            neg_max: (-b.max).extend(0.0),
        }
    }

    #[inline(always)]
    pub fn bounds(self) -> Box3 {
        Box3 {
            min: Vec3A::from_vec4(self.min),
            neg_max: Vec3A::from_vec4(self.neg_max),
        }
    }

    /// Twice the box's centre, `min + max`: bin positions are ratios of differences of
    /// centroids, in which the factor 2 is exact and cancels.
    #[inline(always)]
    pub fn centroid2(self) -> Vec3A {
        Vec3A::from_vec4(self.min) - Vec3A::from_vec4(self.neg_max)
    }

    /// [`Ref::centroid2`] along one axis (the same sum, so the same rounding).
    #[inline(always)]
    pub fn centroid2_on(&self, axis: usize) -> f32 {
        match axis {
            0 => self.min.x - self.neg_max.x,
            1 => self.min.y - self.neg_max.y,
            _ => self.min.z - self.neg_max.z,
        }
    }

    /// The group lanes the primitive's test fills.
    #[inline(always)]
    pub fn slots(&self) -> u32 {
        self.min.w as u32
    }
}

/// The half areas of four boxes at once, each the same products and sums as
/// [`Box3::half_area`].
#[inline(always)]
pub(super) fn half_areas4(b: &[Box3]) -> [f32; 4] {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::*;
        let e: [__m128; 4] =
            std::array::from_fn(|i| (-(b[i].neg_max + b[i].min)).max(Vec3A::ZERO).into());
        // Transpose: one register per coordinate, one lane per box.
        // SAFETY: SSE is part of the x86-64 baseline.
        let (x, y, z) = unsafe {
            let xy01 = _mm_unpacklo_ps(e[0], e[1]);
            let xy23 = _mm_unpacklo_ps(e[2], e[3]);
            let zw01 = _mm_unpackhi_ps(e[0], e[1]);
            let zw23 = _mm_unpackhi_ps(e[2], e[3]);
            (
                Vec4::from(_mm_movelh_ps(xy01, xy23)),
                Vec4::from(_mm_movehl_ps(xy23, xy01)),
                Vec4::from(_mm_movelh_ps(zw01, zw23)),
            )
        };
        (x * y + y * z + z * x).to_array()
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        std::array::from_fn(|i| b[i].half_area())
    }
}

/// The bounds of a node's doubled centroids ([`Ref::centroid2`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct Centroids {
    pub min: Vec3A,
    pub max: Vec3A,
}

impl Centroids {
    pub const EMPTY: Self = Self {
        min: Vec3A::INFINITY,
        max: Vec3A::NEG_INFINITY,
    };

    #[inline(always)]
    pub fn grow(self, p: Vec3A) -> Self {
        Self {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    #[inline(always)]
    pub fn union(self, o: Self) -> Self {
        Self {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }
}
