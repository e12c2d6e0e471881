//! The eight-wide entry: [`enter`], AVX2 lanes taking the scalar entry's steps (see the
//! parent module).

use std::arch::x86_64::*;

use super::Entries;
use crate::geometry::frame::RayFrame;
use crate::geometry::instance::Instance;
use crate::math::slab::HUGE_COMPONENT;
use crate::math::{ROBUST_BOX_SCALE, Ray};

/// The lanes' rays as eight-wide columns.
struct Columns {
    origin: [__m256; 3],
    dir: [__m256; 3],
    t_min: __m256,
    t_max: __m256,
}

/// Eight rows of eight floats as eight columns (and back: the transpose is its own
/// inverse).
#[target_feature(enable = "avx2")]
fn transpose(r: [__m256; 8]) -> [__m256; 8] {
    let t = [
        _mm256_unpacklo_ps(r[0], r[1]),
        _mm256_unpackhi_ps(r[0], r[1]),
        _mm256_unpacklo_ps(r[2], r[3]),
        _mm256_unpackhi_ps(r[2], r[3]),
        _mm256_unpacklo_ps(r[4], r[5]),
        _mm256_unpackhi_ps(r[4], r[5]),
        _mm256_unpacklo_ps(r[6], r[7]),
        _mm256_unpackhi_ps(r[6], r[7]),
    ];
    let u = [
        _mm256_shuffle_ps::<0x44>(t[0], t[2]),
        _mm256_shuffle_ps::<0xEE>(t[0], t[2]),
        _mm256_shuffle_ps::<0x44>(t[1], t[3]),
        _mm256_shuffle_ps::<0xEE>(t[1], t[3]),
        _mm256_shuffle_ps::<0x44>(t[4], t[6]),
        _mm256_shuffle_ps::<0xEE>(t[4], t[6]),
        _mm256_shuffle_ps::<0x44>(t[5], t[7]),
        _mm256_shuffle_ps::<0xEE>(t[5], t[7]),
    ];
    [
        _mm256_permute2f128_ps::<0x20>(u[0], u[4]),
        _mm256_permute2f128_ps::<0x20>(u[1], u[5]),
        _mm256_permute2f128_ps::<0x20>(u[2], u[6]),
        _mm256_permute2f128_ps::<0x20>(u[3], u[7]),
        _mm256_permute2f128_ps::<0x31>(u[0], u[4]),
        _mm256_permute2f128_ps::<0x31>(u[1], u[5]),
        _mm256_permute2f128_ps::<0x31>(u[2], u[6]),
        _mm256_permute2f128_ps::<0x31>(u[3], u[7]),
    ]
}

/// The lanes' rays as eight-wide columns. A [`Ray`] is eight floats in field order
/// (`repr(C)`), so each is one row.
#[target_feature(enable = "avx2")]
fn columns(rays: &[Ray]) -> Columns {
    // Lanes past the rays repeat the first ray (their entries are not written).
    let rows = std::array::from_fn(|k| {
        let r: *const Ray = rays.get(k).unwrap_or(&rays[0]);
        // SAFETY: a ray is eight contiguous floats (`repr(C)`, checked in `math`).
        unsafe { _mm256_loadu_ps(r.cast::<f32>()) }
    });
    let c = transpose(rows);
    Columns {
        origin: [c[0], c[1], c[2]],
        dir: [c[3], c[4], c[5]],
        t_min: c[6],
        t_max: c[7],
    }
}

/// Rust's `f32::max` (a NaN operand gives the other), lane by lane.
#[target_feature(enable = "avx2")]
fn max_num(a: __m256, b: __m256) -> __m256 {
    let m = _mm256_max_ps(a, b);
    let m = _mm256_blendv_ps(m, b, _mm256_cmp_ps::<_CMP_UNORD_Q>(a, a));
    _mm256_blendv_ps(m, a, _mm256_cmp_ps::<_CMP_UNORD_Q>(b, b))
}

/// Rust's `f32::min`, lane by lane.
#[target_feature(enable = "avx2")]
fn min_num(a: __m256, b: __m256) -> __m256 {
    let m = _mm256_min_ps(a, b);
    let m = _mm256_blendv_ps(m, b, _mm256_cmp_ps::<_CMP_UNORD_Q>(a, a));
    _mm256_blendv_ps(m, a, _mm256_cmp_ps::<_CMP_UNORD_Q>(b, b))
}

/// `f32::next_down` of lanes that are not NaN.
#[target_feature(enable = "avx2")]
fn next_down(x: __m256) -> __m256 {
    let bits = _mm256_castps_si256(x);
    let magnitude = _mm256_and_si256(bits, _mm256_set1_epi32(0x7fff_ffff));
    let zero = _mm256_cmpeq_epi32(magnitude, _mm256_setzero_si256());
    let negative = _mm256_cmpgt_epi32(_mm256_setzero_si256(), bits);
    let neg_inf = _mm256_cmpeq_epi32(bits, _mm256_set1_epi32(0xff80_0000u32 as i32));
    // Away from zero for negatives (+1), towards it for positives (-1).
    let stepped = _mm256_blendv_epi8(
        _mm256_sub_epi32(bits, _mm256_set1_epi32(1)),
        _mm256_add_epi32(bits, _mm256_set1_epi32(1)),
        negative,
    );
    let out = _mm256_blendv_epi8(stepped, _mm256_set1_epi32(0x8000_0001u32 as i32), zero);
    let out = _mm256_blendv_epi8(out, bits, neg_inf);
    _mm256_castsi256_ps(out)
}

/// Entries of `rays` into `inst` for the lanes the common case covers, written to `out`;
/// returns those lanes as a bit mask (the caller enters the others one at a time).
#[target_feature(enable = "avx2")]
pub(super) fn enter(inst: &Instance, rays: &[Ray], frame: &RayFrame, out: &mut Entries) -> u32 {
    let c = columns(rays);
    let splat = |v: f32| _mm256_set1_ps(v);
    let abs = |v: __m256| _mm256_andnot_ps(splat(-0.0), v);
    let region = inst.frame.near_region();
    let mut ok = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    // The origin in the near region (traced as given), as `RayFrame::holds`.
    for a in 0..3 {
        let o = c.origin[a];
        ok = _mm256_and_ps(ok, _mm256_cmp_ps::<_CMP_GE_OQ>(o, splat(region.min[a])));
        ok = _mm256_and_ps(ok, _mm256_cmp_ps::<_CMP_LE_OQ>(o, splat(region.max[a])));
    }
    // The plain f32 slab test applies (`SlabKind::Finite`).
    let inv = c.dir.map(|d| _mm256_div_ps(splat(1.0), d));
    for (a, &d) in c.dir.iter().enumerate() {
        let zero = _mm256_cmp_ps::<_CMP_EQ_OQ>(d, splat(0.0));
        let normal = _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_GE_OQ>(abs(inv[a]), splat(f32::MIN_POSITIVE)),
            _mm256_cmp_ps::<_CMP_LT_OQ>(abs(inv[a]), splat(f32::INFINITY)),
        );
        let huge = _mm256_cmp_ps::<_CMP_GT_OQ>(abs(d), splat(HUGE_COMPONENT));
        let plain = _mm256_andnot_ps(_mm256_or_ps(zero, huge), normal);
        ok = _mm256_and_ps(ok, plain);
    }
    let covered = _mm256_movemask_ps(ok) as u32 & ((1u32 << rays.len()) - 1);
    if covered == 0 {
        return 0;
    }
    // The box's entry and exit (`Aabb::hit_range_with`, over all t).
    let mut lo = [splat(0.0); 3];
    let mut hi = [splat(0.0); 3];
    for a in 0..3 {
        let t0 = _mm256_mul_ps(
            _mm256_sub_ps(splat(inst.bounds.min[a]), c.origin[a]),
            inv[a],
        );
        let t1 = _mm256_mul_ps(
            _mm256_sub_ps(splat(inst.bounds.max[a]), c.origin[a]),
            inv[a],
        );
        lo[a] = _mm256_min_ps(t0, t1);
        hi[a] = _mm256_max_ps(t0, t1);
    }
    // glam's `max_element` and `min_element`: (x op z) op (y op z).
    let near = _mm256_max_ps(_mm256_max_ps(lo[0], lo[2]), _mm256_max_ps(lo[1], lo[2]));
    let near = max_num(near, splat(f32::NEG_INFINITY));
    let far = _mm256_min_ps(_mm256_min_ps(hi[0], hi[2]), _mm256_min_ps(hi[1], hi[2]));
    let far = min_num(
        max_num(far, _mm256_mul_ps(far, splat(ROBUST_BOX_SCALE))),
        splat(f32::INFINITY),
    );
    let crosses = _mm256_cmp_ps::<_CMP_LE_OQ>(near, far);
    // Clipped to the box (`Geometry::clipped_object_ray`); empty or NaN: nothing to find.
    let t_min = max_num(c.t_min, next_down(near));
    let t_max = min_num(c.t_max, far);
    let inside = _mm256_and_ps(crosses, _mm256_cmp_ps::<_CMP_LT_OQ>(t_min, t_max));
    // The object-space ray (`Placement::object_ray`), four lanes at a time in f64.
    let m = inst.placement.world_to_object();
    let cols = [m.matrix3.x_axis, m.matrix3.y_axis, m.matrix3.z_axis];
    let mut origin = [[0.0f32; 4]; 6];
    let mut dir = [[0.0f32; 4]; 6];
    for half in 0..2 {
        let wide = |v: __m256| {
            let part = if half == 0 {
                _mm256_castps256_ps128(v)
            } else {
                _mm256_extractf128_ps::<1>(v)
            };
            _mm256_cvtps_pd(part)
        };
        let (o, d) = (c.origin.map(wide), c.dir.map(wide));
        for row in 0..3 {
            let term = |col: usize, v: __m256d| _mm256_mul_pd(_mm256_set1_pd(cols[col][row]), v);
            let od = _mm256_add_pd(_mm256_add_pd(term(0, o[0]), term(1, o[1])), term(2, o[2]));
            let od = _mm256_add_pd(od, _mm256_set1_pd(m.translation[row]));
            let dd = _mm256_add_pd(_mm256_add_pd(term(0, d[0]), term(1, d[1])), term(2, d[2]));
            // SAFETY: four floats each.
            unsafe {
                _mm_storeu_ps(origin[2 * row + half].as_mut_ptr(), _mm256_cvtpd_ps(od));
                _mm_storeu_ps(dir[2 * row + half].as_mut_ptr(), _mm256_cvtpd_ps(dd));
            }
        }
    }
    // SAFETY: eight floats each.
    let load = |v: &[[f32; 4]; 6], a: usize| unsafe {
        _mm256_loadu2_m128(v[2 * a + 1].as_ptr(), v[2 * a].as_ptr())
    };
    let origin: [__m256; 3] = std::array::from_fn(|a| load(&origin, a));
    let dir: [__m256; 3] = std::array::from_fn(|a| load(&dir, a));
    // A usable image: finite, with a non-zero direction.
    let mut finite = inside;
    let mut moving = _mm256_setzero_ps();
    for a in 0..3 {
        let (o, d) = (origin[a], dir[a]);
        finite = _mm256_and_ps(
            finite,
            _mm256_cmp_ps::<_CMP_LT_OQ>(abs(o), splat(f32::INFINITY)),
        );
        finite = _mm256_and_ps(
            finite,
            _mm256_cmp_ps::<_CMP_LT_OQ>(abs(d), splat(f32::INFINITY)),
        );
        moving = _mm256_or_ps(moving, _mm256_cmp_ps::<_CMP_NEQ_UQ>(d, splat(0.0)));
    }
    let usable = _mm256_and_ps(finite, moving);
    // Held by `frame`, as `RayFrame::holds`.
    let walked_region = frame.near_region();
    let mut held = usable;
    for (a, &o) in origin.iter().enumerate() {
        let (lo, hi) = (walked_region.min[a], walked_region.max[a]);
        held = _mm256_and_ps(held, _mm256_cmp_ps::<_CMP_GE_OQ>(o, splat(lo)));
        held = _mm256_and_ps(held, _mm256_cmp_ps::<_CMP_LE_OQ>(o, splat(hi)));
    }
    let (usable, held) = (
        _mm256_movemask_ps(usable) as u32,
        _mm256_movemask_ps(held) as u32,
    );
    // The object-space rays as rows, written whole; only the usable covered lanes count.
    let rows = transpose([
        origin[0], origin[1], origin[2], dir[0], dir[1], dir[2], t_min, t_max,
    ]);
    for (k, row) in rows.iter().enumerate() {
        let r: *mut Ray = &mut out.objects[k];
        // SAFETY: a ray is eight contiguous floats (`repr(C)`, checked in `math`).
        unsafe { _mm256_storeu_ps(r.cast::<f32>(), *row) };
    }
    out.object = (out.object & !covered) | (covered & usable);
    out.framed &= !covered;
    out.held = (out.held & !covered) | (covered & held);
    covered
}
