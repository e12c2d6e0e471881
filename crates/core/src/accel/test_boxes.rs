//! Test inputs the builders' unit tests share: only boxes, as the builders see them.

use crate::math::{Aabb, Vec3};

/// `n` seeded boxes scattered over a 100-unit cube, some tiny, some long (xorshift64, so the
/// same seed gives the same boxes everywhere).
pub(crate) fn scattered(n: usize, seed: u64) -> Vec<Aabb> {
    let mut s = 0x9e37_79b9_7f4a_7c15u64 ^ seed;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..n)
        .map(|_| {
            let c = Vec3::new(next(), next(), next()) * 100.0;
            let e = Vec3::new(next(), next(), next()) * next() * 10.0;
            Aabb::new(c - e, c + e)
        })
        .collect()
}
