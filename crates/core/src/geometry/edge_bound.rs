//! The rounding-error bound of the watertight test's `f32` edge functions: an edge function
//! whose magnitude exceeds it has the sign of the exact one, so the test may decide on it;
//! within it, the edge is re-evaluated in `f64` (and exactly where that is not enough).
//!
//! The bound follows the error from its sources instead of from the vertices' distances alone.
//! A sheared coordinate `x' = (p - o)[kx] - sx (p - o)[kz]` errs by at most `4.01 u Mx` with
//! `Mx = |(p - o)[kx]| + |sx| |(p - o)[kz]|` (`u = 2^-24`: the difference `p - o`, the ratio
//! `sx`, the product and the subtraction each round once); likewise `y'` with `My`. The edge
//! function `e = px' qy' - py' qx'` then errs by at most
//!
//! ```text
//! 2.0001 u (|px' qy'| + |py' qx'|)                       (its own two products and difference)
//!   + 4.01 u (|px'| My_q + |qy'| Mx_p + |py'| Mx_q + |qx'| My_p)   (the inputs' errors)
//!   + (4.01 u)^2 (Mx_p My_q + Mx_q My_p)                  (their product)
//! ```
//!
//! which [`edge_bound`] covers with the constants [`G2`] = 3u, [`G`] = 8u, [`GG`] = 64u^2: the
//! slack absorbs the bound's own roundings (a dozen operations, each relative `u`). Near a
//! triangle edge `|px'|` etc. are the triangle's size seen from the ray, not the distance, so
//! the bound is about `distance x size x 2^-21`: a ray has to pass within ~1e-6 of the
//! triangle's size from an edge to need `f64`. (The earlier bound, a product of the two
//! vertices' distances, sent a third of the 69k-triangle bunny's candidates and nearly all of
//! the 1.1M one's to `f64`.)
//!
//! Below the normal range roundings are absolute: [`SHEAR_UNDERFLOW`] widens `|sx|`, [`TINY`]
//! each magnitude, and [`ABS_TINY`] the sum (see each). Overflow makes the bound infinite or
//! NaN, which always refines.
//!
//! The bound of an edge depends only on its two vertices and is symmetric in them (every sum
//! pairs terms whose order a reversed edge swaps, and two-term sums commute), so both triangles
//! sharing an edge refine it alike. Each decision is the exact sign either way.

/// `3 u`, at least `gamma(2)` of the edge function's products and difference plus slack.
pub(crate) const G2: f32 = 3.0 * f32::EPSILON * 0.5;
/// `8 u`, at least the `4.01 u` of a sheared coordinate's error plus slack.
pub(crate) const G: f32 = 8.0 * f32::EPSILON * 0.5;
/// `G * G`.
pub(crate) const GG: f32 = G * G;

/// Added to `|sx|`, `|sy|`: a ratio below the normal range errs by up to 2^-150 absolutely,
/// which moves `x'` by `2^-150 |(p - o)[kz]|`; `G * 2^-126 * |(p - o)[kz]|` covers it.
pub(crate) const SHEAR_UNDERFLOW: f32 = f32::MIN_POSITIVE;

/// Added to each `Mx`, `My`: the product `sx (p - o)[kz]` below the normal range errs by up to
/// 2^-150 absolutely; `G * 2^-126` covers it.
pub(crate) const TINY: f32 = f32::MIN_POSITIVE;

/// Added to the bound: the edge function's products below the normal range err by up to 2^-150
/// each, and the bound's own products and sums there as much again (a dozen of them): 2^-144
/// covers all of it.
pub(crate) const ABS_TINY: f32 = f32::from_bits(32);

/// A vertex's sheared magnitudes `(Mx, My)` from its offset `a = p - o` (world axes), for
/// shear axes `k` and widened ratios `w = (|sx| + SHEAR_UNDERFLOW, |sy| + SHEAR_UNDERFLOW)`.
#[inline(always)]
pub(crate) fn magnitudes(a: [f32; 3], k: [usize; 3], w: [f32; 2]) -> (f32, f32) {
    let z = a[k[2]].abs();
    (
        (a[k[0]].abs() + w[0] * z) + TINY,
        (a[k[1]].abs() + w[1] * z) + TINY,
    )
}

/// The bound of the edge function `e = px qy - py qx`, given its two products `pq = px qy`,
/// `qp = py qx` as computed, the sheared coordinates and the magnitudes `(Mx, My)` of `p`, `q`.
/// [`super::triangle`] and the packed leaves' SIMD pass compute it with these operations in
/// this order.
#[inline(always)]
pub(crate) fn edge_bound(
    [pq, qp]: [f32; 2],
    [px, py]: [f32; 2],
    [qx, qy]: [f32; 2],
    (mxp, myp): (f32, f32),
    (mxq, myq): (f32, f32),
) -> f32 {
    let own = G2 * (pq.abs() + qp.abs());
    let inputs = G * ((px.abs() * myq + qy.abs() * mxp) + (py.abs() * mxq + qx.abs() * myp));
    let cross = GG * (mxp * myq + mxq * myp);
    ((own + inputs) + cross) + ABS_TINY
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::exact::edge_sign;
    use crate::geometry::triangle::WatertightRay;
    use crate::math::Vec3;
    use crate::rng::SampleRng;
    use std::cmp::Ordering;

    /// The renderer's seeded stream, as `f64` in [0, 1) and [-1, 1).
    struct Rng(SampleRng);
    impl Rng {
        fn new(seed: u64) -> Self {
            Self(SampleRng::new(seed, 0, 0, 0))
        }
        fn next(&mut self) -> f64 {
            self.0.next_f32() as f64
        }
        fn signed(&mut self) -> f64 {
            2.0 * self.next() - 1.0
        }
    }

    /// The `f32` edge function of `p`, `q` and whether it lies outside its bound, computed as
    /// the triangle test computes it.
    fn f32_edge(o: Vec3, wr: &WatertightRay, p: Vec3, q: Vec3) -> (f32, f32) {
        let k = [wr.kx, wr.ky, wr.kz];
        let shear = |v: Vec3| {
            let a = (v - o).to_array();
            let s = (a[k[0]] - wr.sx * a[k[2]], a[k[1]] - wr.sy * a[k[2]]);
            (s, magnitudes(a, k, wr.w))
        };
        let (((px, py), mp), ((qx, qy), mq)) = (shear(p), shear(q));
        let (pq, qp) = (px * qy, py * qx);
        let e = pq - qp;
        (e, edge_bound([pq, qp], [px, py], [qx, qy], mp, mq))
    }

    #[test]
    fn an_edge_outside_its_bound_has_the_exact_sign() {
        // Rays aimed at points 10^-12 .. 10^-2 of the edge's length beside a random edge, at
        // scales from 1e-20 to 1e20, origins near and far, directions with tiny components:
        // wherever the f32 value is trusted, its sign must be the exact one.
        let mut rng = Rng::new(7);
        let (mut trusted, mut tight) = (0, 0);
        for i in 0..200_000 {
            let scale = 10f64.powf(rng.signed() * 20.0);
            let v = |rng: &mut Rng| {
                Vec3::new(
                    rng.signed() as f32,
                    rng.signed() as f32,
                    rng.signed() as f32,
                )
            };
            let (p, q) = (v(&mut rng) * scale as f32, v(&mut rng) * scale as f32);
            // A point beside the edge, by a relative offset spread over many decades.
            let s = rng.next();
            let off = 10f64.powf(-2.0 - 10.0 * rng.next()) * rng.signed().signum();
            let side = v(&mut rng);
            let target = p.as_dvec3()
                + (q - p).as_dvec3() * s
                + side.as_dvec3() * (q - p).as_dvec3().length() * off;
            let mut d = v(&mut rng);
            if i % 5 == 0 {
                d[i % 3] *= 1e-12; // a nearly axis-parallel ray
            }
            if d.length() == 0.0 {
                continue;
            }
            let dist = scale * 10f64.powf(rng.next() * 4.0); // near to 1e4 sizes away
            let o = (target - d.as_dvec3().normalize() * dist).as_vec3();
            let wr = WatertightRay::new(d);
            let (e, bound) = f32_edge(o, &wr, p, q);
            // Within the bound, or a NaN bound: refined, not trusted.
            if e.abs().partial_cmp(&bound) != Some(Ordering::Greater) {
                continue;
            }
            trusted += 1;
            // `edge_sign` of the directed edge q -> p is the sign of `px qy - py qx`.
            let exact = edge_sign(o, d, q, p, [wr.kx, wr.ky, wr.kz]);
            let sign = if e > 0.0 {
                Ordering::Greater
            } else {
                Ordering::Less
            };
            assert_eq!(sign, exact, "p {p:?} q {q:?} o {o:?} d {d:?}: e = {e}");
            // The cases that test the bound: trusted with little to spare.
            if e.abs() < 16.0 * bound {
                tight += 1;
            }
        }
        assert!(trusted > 20_000 && tight > 1_000, "{trusted} {tight}");
    }

    #[test]
    fn the_bound_is_symmetric_in_the_edge_s_vertices() {
        // A reversed edge (the neighbour's) refines exactly when this one does.
        let mut rng = Rng::new(11);
        for _ in 0..100_000 {
            let f = |rng: &mut Rng| (rng.signed() * 10f64.powf(rng.signed() * 10.0)) as f32;
            let (px, py, qx, qy) = (f(&mut rng), f(&mut rng), f(&mut rng), f(&mut rng));
            let (mp, mq) = (
                (f(&mut rng).abs(), f(&mut rng).abs()),
                (f(&mut rng).abs(), f(&mut rng).abs()),
            );
            let forward = edge_bound([px * qy, py * qx], [px, py], [qx, qy], mp, mq);
            let reversed = edge_bound([qx * py, qy * px], [qx, qy], [px, py], mq, mp);
            assert_eq!(forward.to_bits(), reversed.to_bits());
        }
    }

    #[test]
    fn the_constants_cover_the_error_terms() {
        // 3u covers gamma(2) plus the bound's own dozen roundings; 8u covers 4.01u likewise.
        let u = f32::EPSILON as f64 / 2.0;
        let own_rounding = 1.0 + 16.0 * u;
        assert!(G2 as f64 >= crate::math::gamma(2) as f64 * own_rounding);
        assert!(G as f64 >= 4.01 * u * own_rounding);
        assert!(GG as f64 >= (4.01 * u).powi(2) * own_rounding);
        assert!(ABS_TINY as f64 >= 16.0 * 2f64.powi(-150) * 2.0);
    }
}
