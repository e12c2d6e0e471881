//! Vector types, rays, axis-aligned boxes and the robust origin offset for secondary rays.
//!
//! All geometry is world space `f32`; `f64` appears only where an accuracy case needs it
//! (the triangle test's fallback).

pub mod slab;

pub use glam::{Mat3, Mat4, Vec2, Vec3, Vec3A, Vec4};

/// A ray `origin + t * dir`, valid for `t_min < t <= t_max` (world space).
///
/// `dir` need not be normalised: `t` is measured in units of `dir`.
///
/// `repr(C)`: eight `f32`s in field order, so that eight rays load as the rows of an 8x8 block
/// (`geometry::instance_entries`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: Vec3,
    /// Its direction (any non-zero length).
    pub dir: Vec3,
    /// Hits at or below this parameter are ignored.
    pub t_min: f32,
    /// Hits beyond this parameter are ignored; accelerators shrink it as they find hits.
    pub t_max: f32,
}

// The layout `repr(C)` promises: origin, direction, `t_min`, `t_max`, no padding.
const _: () = {
    assert!(std::mem::size_of::<Ray>() == 32);
    assert!(std::mem::offset_of!(Ray, dir) == 12);
    assert!(std::mem::offset_of!(Ray, t_min) == 24);
    assert!(std::mem::offset_of!(Ray, t_max) == 28);
};

impl Ray {
    /// A ray over `(0, inf]`.
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self {
            origin,
            dir,
            t_min: 0.0,
            t_max: f32::INFINITY,
        }
    }

    /// A ray over `(0, t_max]`.
    pub fn segment(origin: Vec3, dir: Vec3, t_max: f32) -> Self {
        Self {
            origin,
            dir,
            t_min: 0.0,
            t_max,
        }
    }

    /// The point at parameter `t`.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// An axis-aligned bounding box; `Aabb::EMPTY` is the identity of `union`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
}

impl Aabb {
    /// The empty box: `min = +inf`, `max = -inf`.
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// The box spanning two corners given in any order.
    pub fn new(a: Vec3, b: Vec3) -> Self {
        Self {
            min: a.min(b),
            max: a.max(b),
        }
    }

    /// The smallest box holding every point.
    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Self {
        points.into_iter().fold(Self::EMPTY, |b, p| b.grow(p))
    }

    /// This box enlarged to hold `p`.
    pub fn grow(self, p: Vec3) -> Self {
        Self {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// The smallest box holding both.
    pub fn union(self, o: Aabb) -> Self {
        Self {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// True when the box holds no point.
    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// Edge lengths (zero for an empty box).
    pub fn extent(&self) -> Vec3 {
        if self.is_empty() {
            Vec3::ZERO
        } else {
            self.max - self.min
        }
    }

    /// The centre point.
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Surface area (zero for an empty box), used by the SAH.
    pub fn surface_area(&self) -> f32 {
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    /// True when `o` lies inside this box (boundaries included).
    pub fn contains(&self, o: &Aabb) -> bool {
        self.min.cmple(o.min).all() && self.max.cmpge(o.max).all()
    }

    /// Index of the longest axis.
    pub fn longest_axis(&self) -> usize {
        let e = self.extent();
        if e.x >= e.y && e.x >= e.z {
            0
        } else if e.y >= e.z {
            1
        } else {
            2
        }
    }

    /// Entry and exit parameters of `ray` within `[t_min, t_max]`, or `None` when it misses.
    ///
    /// `inv_dir` comes from [`safe_inverse`] (infinite where the direction is zero). The exit
    /// distance is widened by 2 ulp-scale factors (Ize 2013) so that a box exactly touching a
    /// hit is never culled by rounding. Boxes are closed: a ray lying in a box's face plane
    /// (zero direction component, origin exactly on the plane) is inside that slab.
    #[inline(always)]
    pub fn hit_range(
        &self,
        origin: Vec3A,
        inv_dir: Vec3A,
        t_min: f32,
        t_max: f32,
    ) -> Option<(f32, f32)> {
        self.hit_range_with::<true>(origin, inv_dir, t_min, t_max)
    }

    /// [`Aabb::hit_range`], with the `0 * inf` handling compiled in only when `AXIS_PARALLEL`:
    /// pass `false` only when every component of `inv_dir` is finite (then no lane can be NaN).
    /// Traversals pick once per ray; the check costs ~15% on coherent rays where it is not needed.
    #[inline(always)]
    pub fn hit_range_with<const AXIS_PARALLEL: bool>(
        &self,
        origin: Vec3A,
        inv_dir: Vec3A,
        t_min: f32,
        t_max: f32,
    ) -> Option<(f32, f32)> {
        let t0 = (Vec3A::from(self.min) - origin) * inv_dir;
        let t1 = (Vec3A::from(self.max) - origin) * inv_dir;
        // `0 * inf = NaN` exactly when a zero direction component meets an origin on that slab's
        // plane: the ray then runs inside the closed slab, so that axis must not limit the range.
        // (A finite stand-in for 1/0 would give t = 0 there instead and cull the box wrongly.)
        let (mut lo, mut hi) = (t0.min(t1), t0.max(t1));
        if AXIS_PARALLEL {
            let on_plane = t0.is_nan_mask() | t1.is_nan_mask();
            lo = Vec3A::select(on_plane, Vec3A::NEG_INFINITY, lo);
            hi = Vec3A::select(on_plane, Vec3A::INFINITY, hi);
        }
        let near = lo.max_element().max(t_min);
        let far = hi.min_element();
        // Widening by a factor moves a negative exit towards -inf, so only positive exits are scaled.
        let far = far.max(far * ROBUST_BOX_SCALE).min(t_max);
        (near <= far).then_some((near, far))
    }
}

/// The component-wise reciprocal of a direction for [`Aabb::hit_range`]: IEEE division, so a
/// zero component gives a signed infinity and the slab test stays exact for axis-parallel rays
/// (a finite stand-in such as `1 / 1e-30` turns an origin on a slab plane into `t = 0` and
/// culls boxes the ray runs along). The `0 * inf` case is resolved in `hit_range`.
pub fn safe_inverse(dir: Vec3) -> Vec3A {
    Vec3A::ONE / Vec3A::from(dir)
}

/// The largest `f32` not above `x`: an `f64` rounded towards -inf, for bounds that must hold.
#[inline]
pub fn f32_down(x: f64) -> f32 {
    let y = x as f32;
    if (y as f64) > x { y.next_down() } else { y }
}

/// The smallest `f32` not below `x`: an `f64` rounded towards +inf, for bounds that must hold.
#[inline]
pub fn f32_up(x: f64) -> f32 {
    let y = x as f32;
    if (y as f64) < x { y.next_up() } else { y }
}

/// `x.floor()`, bit for bit, without the library call: the baseline x86-64 target has no
/// rounding instruction (SSE4.1), so `f32::floor` is a call into libm, and the noise textures
/// take three per lookup. Below 2^23 in magnitude, truncation through `i32` and one correction
/// give the floor, and `copysign` restores -0.0; beyond, every float is an integer (or NaN or
/// infinite) and is its own floor.
#[inline]
pub fn floor_fast(x: f32) -> f32 {
    if x.abs() < 8_388_608.0 {
        let t = x as i32 as f32;
        (t - f32::from(u8::from(t > x))).copysign(x)
    } else {
        x
    }
}

/// `1 + 2 * gamma(3)`: the factor that makes the slab test conservative (pbrt-v4, Ize 2013).
pub(crate) const ROBUST_BOX_SCALE: f32 = 1.0 + 2.0 * gamma(3);

/// The floating-point error bound `n * eps / (1 - n * eps)` (pbrt's gamma_n), with eps = 2^-24.
pub const fn gamma(n: i32) -> f32 {
    let e = f32::EPSILON * 0.5;
    (n as f32 * e) / (1.0 - n as f32 * e)
}

/// Moves a surface point off the surface along the geometric normal `n`, on the side `dir` points
/// to, by a distance that scales with the point's magnitude (Ray Tracing Gems, ch. 6).
///
/// Rays started from the result neither re-hit the surface they leave (acne) nor skip a nearby
/// one, at any distance from the origin: the offset is a few float ulps of `p`, not an epsilon.
pub fn offset_ray_origin(p: Vec3, n: Vec3, dir: Vec3) -> Vec3 {
    const ORIGIN: f32 = 1.0 / 32.0;
    const FLOAT_SCALE: f32 = 1.0 / 65536.0;
    const INT_SCALE: f32 = 256.0;
    let n = if n.dot(dir) < 0.0 { -n } else { n };
    let of_i = (n * INT_SCALE).as_ivec3();
    let step = |p: f32, o: i32| {
        // Adding to the integer bit pattern moves `p` by `o` ulps, away from zero when o and p share a sign.
        let bits = p.to_bits() as i32;
        f32::from_bits(bits.wrapping_add(if p < 0.0 { -o } else { o }) as u32)
    };
    let p_i = Vec3::new(step(p.x, of_i.x), step(p.y, of_i.y), step(p.z, of_i.z));
    let pick = |p: f32, p_i: f32, n: f32| {
        if p.abs() < ORIGIN {
            p + FLOAT_SCALE * n
        } else {
            p_i
        }
    };
    Vec3::new(
        pick(p.x, p_i.x, n.x),
        pick(p.y, p_i.y, n.y),
        pick(p.z, p_i.z, n.z),
    )
}

/// An orthonormal basis `(t, b)` completing unit vector `n` (Duff et al. 2017).
pub fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_fast_is_floor_bit_for_bit() {
        let mut specials = vec![
            0.0f32,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            1e-45,
            -1e-45,
            8_388_607.5,
            -8_388_607.5,
            8_388_608.0,
            -8_388_609.0,
            1e30,
            -1e30,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        // Every float next to each integer from -300 to 300, and a sweep of bit patterns.
        for i in -300..=300 {
            let f = i as f32;
            specials.extend([f, f.next_up(), f.next_down()]);
        }
        specials.extend((0..200_000u32).map(|k| f32::from_bits(k.wrapping_mul(0x9E37_79B9))));
        for x in specials {
            let (a, b) = (floor_fast(x), x.floor());
            assert!(
                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                "floor_fast({x:e}) = {a:e}, floor = {b:e}"
            );
        }
    }

    #[test]
    fn offset_moves_to_the_requested_side_at_any_magnitude() {
        for scale in [1e-3f32, 1.0, 1e3, 1e6, 1e7] {
            let p = Vec3::new(0.3, -0.7, 0.9) * scale;
            let n = Vec3::new(0.2, 0.9, -0.1).normalize();
            let up = offset_ray_origin(p, n, n);
            let down = offset_ray_origin(p, n, -n);
            assert!((up - p).dot(n) > 0.0, "scale {scale}");
            assert!((down - p).dot(n) < 0.0, "scale {scale}");
        }
    }

    #[test]
    fn slab_test_handles_axis_parallel_rays() {
        let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let o = Vec3A::new(0.5, 0.5, -1.0);
        let inv = safe_inverse(Vec3::Z);
        let (near, far) = b.hit_range(o, inv, 0.0, f32::INFINITY).unwrap();
        assert!((near - 1.0).abs() < 1e-6 && (far - 2.0).abs() < 1e-5);
        let miss = Vec3A::new(1.5, 0.5, -1.0);
        assert!(b.hit_range(miss, inv, 0.0, f32::INFINITY).is_none());
    }

    #[test]
    fn slab_test_keeps_rays_lying_in_a_face_plane() {
        // Origin on the x = 1 and y = 0 faces, moving along -z (and along -x): inside the closed box.
        let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let o = Vec3A::new(1.0, 0.0, 2.0);
        let (near, far) = b
            .hit_range(o, safe_inverse(-Vec3::Z), 0.0, f32::INFINITY)
            .unwrap();
        assert!((near - 1.0).abs() < 1e-6 && (far - 2.0).abs() < 1e-5);
        let flat = Aabb::new(Vec3::new(0.0, 0.0, 2.0), Vec3::new(1.0, 1.0, 2.0));
        let dir = Vec3::new(-1.0, 0.0, 0.0);
        assert!(
            flat.hit_range(o, safe_inverse(dir), 0.0, f32::INFINITY)
                .is_some()
        );
        // Negative zero gives -inf, and an origin just off the plane still misses.
        let off = Vec3A::new(1.0, -1e-6, 2.0);
        let dir = Vec3::new(-1.0, -0.0, 0.0);
        assert!(
            flat.hit_range(off, safe_inverse(dir), 0.0, f32::INFINITY)
                .is_none()
        );
    }
}
