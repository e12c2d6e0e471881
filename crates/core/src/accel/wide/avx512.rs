//! The child test and child ordering with AVX-512 (F and VL, on 256-bit registers): the
//! entered lanes come from a mask compare straight into a mask register, and the entered
//! children are put in front-to-back order by compressing them to the low lanes and ranking
//! them with mask compares, without the branches of a sort. The distances are the AVX2
//! test's, computed by the same instructions (subtraction then product, no fused
//! multiply-add), so the lanes entered and their entry distances are the same bits; the order
//! is the same too, so every walk visits the same nodes in the same order on either path.

#![cfg(target_arch = "x86_64")]

use std::arch::x86_64::*;

use super::WideNode;
use super::child_test::{ChildTest, Octant};
use super::walk::{Entry, Stack, push_entered};
use crate::accel::bvh::CullBound;
use crate::math::{Aabb, ROBUST_BOX_SCALE, Ray};

/// The 8-lane test with AVX-512 mask compares. Only constructed once the CPU is known to have
/// AVX-512 F and VL besides AVX2 ([`super::SimdPath::Avx512`]).
#[derive(Clone, Copy)]
pub(crate) struct Avx512(pub Octant);

impl ChildTest<8> for Avx512 {
    #[inline(always)]
    fn cull_bound(&self, ray: &Ray, root: &Aabb) -> CullBound {
        CullBound::with_inverse(ray, root, self.0.inv)
    }

    #[inline(always)]
    fn test(&self, node: &WideNode<8>, t_min: f32, t_max: f32) -> (u32, [f32; 8]) {
        // SAFETY: `Avx512` values exist only where AVX-512 F/VL and AVX2 were detected.
        unsafe { avx512_test(&self.0, node, t_min, t_max) }
    }

    #[inline(always)]
    fn push_entered<const N: usize>(
        &self,
        node: &WideNode<8>,
        mask: u32,
        near: &[f32; 8],
        stack: &mut Stack<N>,
    ) -> Option<Entry> {
        // SAFETY: as above.
        unsafe { push_ranked(node, mask, near, stack) }
    }
}

#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl")]
#[inline]
fn avx512_test(o: &Octant, node: &WideNode<8>, t_min: f32, t_max: f32) -> (u32, [f32; 8]) {
    let p = node.planes.as_ptr().cast::<u8>();
    // SAFETY: every offset is that of a row of 8 f32 inside `planes` (the `Octant` invariant).
    let load = |k: usize| unsafe { _mm256_loadu_ps(p.add(o.row_bytes[k] as usize).cast()) };
    let axis = |a: usize| {
        let (org, inv) = (_mm256_set1_ps(o.origin[a]), _mm256_set1_ps(o.inv[a]));
        let near = _mm256_mul_ps(_mm256_sub_ps(load(2 * a), org), inv);
        let far = _mm256_mul_ps(_mm256_sub_ps(load(2 * a + 1), org), inv);
        (near, far)
    };
    entered([axis(0), axis(1), axis(2)], t_min, t_max)
}

/// [`super::child_test::entered`] with the comparison into a mask register: the same
/// distances, the same lanes.
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl")]
#[inline]
pub(super) fn entered(axes: [(__m256, __m256); 3], t_min: f32, t_max: f32) -> (u32, [f32; 8]) {
    let [(nx, fx), (ny, fy), (nz, fz)] = axes;
    let near = _mm256_max_ps(
        _mm256_max_ps(nx, ny),
        _mm256_max_ps(nz, _mm256_set1_ps(t_min)),
    );
    let far = _mm256_min_ps(_mm256_min_ps(fx, fy), fz);
    let widened = _mm256_max_ps(far, _mm256_mul_ps(far, _mm256_set1_ps(ROBUST_BOX_SCALE)));
    let far = _mm256_min_ps(widened, _mm256_set1_ps(t_max));
    let mask = _mm256_cmp_ps_mask::<_CMP_LE_OQ>(near, far) as u32;
    let mut out = [0.0f32; 8];
    // SAFETY: `out` holds 8 f32.
    unsafe { _mm256_storeu_ps(out.as_mut_ptr(), near) };
    (mask, out)
}

/// [`push_entered`] for three or more entered lanes without a sort: the entered lanes are
/// compressed to the low lanes, each one's place in the farthest-first order is counted with
/// a mask compare against every other (a farther one, or an equally far one of a lower lane,
/// goes before it: the order the insertion sort of [`push_entered`] leaves), and each is
/// written straight to its place above the stack's top. One or two lanes take
/// [`push_entered`]'s own cheaper paths.
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt,avx512f,avx512vl")]
#[inline]
pub(super) fn push_ranked<const N: usize>(
    node: &WideNode<8>,
    mask: u32,
    near: &[f32; 8],
    stack: &mut Stack<N>,
) -> Option<Entry> {
    let n = mask.count_ones() as usize;
    if n < 3 {
        return push_entered(node, mask, near, stack);
    }
    let m = mask as __mmask8;
    // SAFETY: each array holds 8 lanes of 4 bytes (unaligned loads).
    let (near_v, child_v, count_v) = unsafe {
        (
            _mm256_maskz_compress_ps(m, _mm256_loadu_ps(near.as_ptr())),
            _mm256_maskz_compress_epi32(m, _mm256_loadu_si256(node.child.as_ptr().cast())),
            _mm256_maskz_compress_epi32(m, _mm256_loadu_si256(node.count.as_ptr().cast())),
        )
    };
    let valid = ((1u32 << n) - 1) as __mmask8;
    let one = _mm256_set1_epi32(1);
    let mut place = _mm256_setzero_si256();
    for j in 0..n {
        let nj = _mm256_permutevar8x32_ps(near_v, _mm256_set1_epi32(j as i32));
        // Entry `j` goes before the nearer ones, and before equally near ones above it.
        let nearer = _mm256_mask_cmp_ps_mask::<_CMP_LT_OQ>(valid, near_v, nj);
        let above = valid & !((2u32 << j) - 1) as __mmask8;
        let tied = _mm256_mask_cmp_ps_mask::<_CMP_EQ_OQ>(above, near_v, nj);
        place = _mm256_mask_add_epi32(place, nearer | tied, place, one);
    }
    let (mut places, mut nears, mut children, mut counts) =
        ([0u32; 8], [0f32; 8], [0u32; 8], [0u32; 8]);
    // SAFETY: each array holds 8 lanes of 4 bytes (unaligned stores).
    unsafe {
        _mm256_storeu_si256(places.as_mut_ptr().cast(), place);
        _mm256_storeu_ps(nears.as_mut_ptr(), near_v);
        _mm256_storeu_si256(children.as_mut_ptr().cast(), child_v);
        _mm256_storeu_si256(counts.as_mut_ptr().cast(), count_v);
    }
    for k in 0..n {
        stack.put_above(
            places[k] as usize,
            Entry {
                child: children[k],
                count: counts[k],
                near: nears[k],
            },
        );
    }
    // SAFETY: the places are 0..n, each taken once, so the `n` slots above the top are
    // written; the nearest, at the last place, is popped to be visited next.
    unsafe { stack.raise(n) };
    stack.pop()
}

#[cfg(test)]
mod tests {
    use super::super::SimdPath;
    use super::super::child_test::Avx2;
    use super::*;
    use crate::math::{Vec3, safe_inverse};

    /// A small xorshift generator: the tests need many cases, not a statistics-grade stream.
    struct Xorshift(u64);

    impl Xorshift {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }

        fn unit(&mut self) -> f32 {
            (self.next() >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    fn entries<const N: usize>(first: Option<Entry>, stack: &mut Stack<N>) -> Vec<[u32; 3]> {
        let bits = |e: Entry| [e.child, e.count, e.near.to_bits()];
        let mut out: Vec<_> = first.into_iter().map(bits).collect();
        while let Some(e) = stack.pop() {
            out.push(bits(e));
        }
        out
    }

    #[test]
    fn ranked_order_is_the_insertion_sorts_with_ties() {
        if !SimdPath::Avx512.supported() {
            eprintln!("AVX-512 child ordering: not run, this CPU lacks AVX-512 F/VL");
            return;
        }
        let mut rng = Xorshift(0x9e37_79b9_7f4a_7c15);
        let mut node = WideNode::<8>::UNUSED;
        for case in 0..20_000 {
            for lane in 0..8 {
                node.child[lane] = (rng.next() % 1000) as u32;
                node.count[lane] = (rng.next() % 3) as u32;
            }
            let mask = (rng.next() % 256) as u32;
            // Few distinct distances, so ties are common; some equal to zero and negative.
            let near: [f32; 8] = std::array::from_fn(|_| (rng.next() % 5) as f32 - 1.0);
            let (mut a, mut b) = (Stack::<32>::new(), Stack::<32>::new());
            a.push(Entry {
                child: 7,
                count: 0,
                near: 0.5,
            });
            b.push(Entry {
                child: 7,
                count: 0,
                near: 0.5,
            });
            let first_a = push_entered(&node, mask, &near, &mut a);
            // SAFETY: AVX-512 F/VL and AVX2 are present (checked above).
            let first_b = unsafe { push_ranked(&node, mask, &near, &mut b) };
            assert_eq!(
                entries(first_a, &mut a),
                entries(first_b, &mut b),
                "case {case}: mask {mask:08b} near {near:?}"
            );
        }
    }

    #[test]
    fn mask_compare_test_enters_the_avx2_tests_lanes_at_the_same_distances() {
        if !SimdPath::Avx512.supported() {
            eprintln!("AVX-512 child test: not run, this CPU lacks AVX-512 F/VL");
            return;
        }
        let mut rng = Xorshift(0x2545_f491_4f6c_dd1d);
        let mut node = WideNode::<8>::UNUSED;
        let mut entered = 0;
        for case in 0..20_000 {
            let v = |rng: &mut Xorshift| Vec3::new(rng.unit(), rng.unit(), rng.unit()) * 8.0 - 4.0;
            for lane in 0..8 {
                if rng.next().is_multiple_of(8) {
                    continue;
                }
                let (p, q) = (v(&mut rng), v(&mut rng));
                let b = Aabb {
                    min: p.min(q),
                    max: p.max(q),
                };
                node.set(lane, &b, lane as u32, 0);
            }
            let ray = Ray::new(v(&mut rng) * 2.0, v(&mut rng));
            let inv = safe_inverse(ray.dir);
            let octant = Octant::new(&ray, inv.to_array());
            let (t_min, t_max) = (rng.unit() - 0.5, rng.unit() * 10.0);
            let (mask_a, near_a) = Avx2(octant).test(&node, t_min, t_max);
            let (mask_b, near_b) = Avx512(octant).test(&node, t_min, t_max);
            assert_eq!(mask_a, mask_b, "case {case}");
            assert_eq!(
                near_a.map(f32::to_bits),
                near_b.map(f32::to_bits),
                "case {case}"
            );
            entered += mask_a.count_ones();
        }
        assert!(entered > 2_000, "only {entered} lanes entered");
    }
}
