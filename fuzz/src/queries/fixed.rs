//! Exact arithmetic on `f32` inputs as big integers in fixed point: every finite `f32` is an
//! integer multiple of 2^-149, so `x * 2^149` is an integer and sums, differences and products
//! of such values are exact. This is the oracle's arithmetic: the same exactness as the
//! hard-case suite's rationals (tests/hard_cases/exact.rs), without a gcd after every
//! operation, which makes the fuzz target's oracle about ten times faster.
//!
//! A product of `k` fixed-point values carries the scale `2^(149 k)`; [`to_f64`] and [`ratio`]
//! take the scale back out when an exact result is finally rounded.

use num_bigint::{BigInt, Sign};
use num_traits::{ToPrimitive, Zero};

/// Fractional bits of the fixed point: the exponent of the smallest subnormal `f32`.
pub const FRAC: u32 = 149;

/// `x * 2^149` exactly (`x` finite).
pub fn fix(x: f32) -> BigInt {
    debug_assert!(x.is_finite());
    let bits = x.to_bits();
    let exp = (bits >> 23) & 0xff;
    let frac = bits & 0x7f_ffff;
    // value = m * 2^(e - 149): subnormals have e = 0, normals the hidden bit.
    let (m, shift) = if exp == 0 {
        (frac, 0)
    } else {
        (frac | 0x80_0000, exp - 1)
    };
    let v = BigInt::from(m) << shift;
    if bits >> 31 == 1 { -v } else { v }
}

/// `x * 2^149` for a non-negative `f64` bound, rounded up (a tolerance must not shrink).
pub fn fix_up(x: f64) -> BigInt {
    debug_assert!(x >= 0.0 && x.is_finite());
    let scaled = scale2(x, FRAC as i64);
    num_traits::FromPrimitive::from_f64(scaled.ceil()).unwrap_or_else(BigInt::zero) + 1
}

/// An exact vector in fixed point.
#[derive(Clone, Debug, PartialEq)]
pub struct IV(pub [BigInt; 3]);

impl IV {
    /// The fixed-point value of an `f32` vector (finite components).
    pub fn of(v: [f32; 3]) -> Self {
        IV(v.map(fix))
    }

    pub fn sub(&self, o: &IV) -> IV {
        IV([0, 1, 2].map(|i| &self.0[i] - &o.0[i]))
    }

    pub fn add(&self, o: &IV) -> IV {
        IV([0, 1, 2].map(|i| &self.0[i] + &o.0[i]))
    }

    pub fn scale(&self, s: &BigInt) -> IV {
        IV([0, 1, 2].map(|i| &self.0[i] * s))
    }

    pub fn shl(&self, bits: u32) -> IV {
        IV([0, 1, 2].map(|i| &self.0[i] << bits))
    }

    pub fn dot(&self, o: &IV) -> BigInt {
        &self.0[0] * &o.0[0] + &self.0[1] * &o.0[1] + &self.0[2] * &o.0[2]
    }

    pub fn cross(&self, o: &IV) -> IV {
        let (a, b) = (&self.0, &o.0);
        IV([
            &a[1] * &b[2] - &a[2] * &b[1],
            &a[2] * &b[0] - &a[0] * &b[2],
            &a[0] * &b[1] - &a[1] * &b[0],
        ])
    }

    pub fn is_zero(&self) -> bool {
        self.0.iter().all(Zero::is_zero)
    }

    /// The Euclidean length of `self / 2^scale`, in `f64` (relative error a few ulps).
    pub fn norm(&self, scale: u32) -> f64 {
        let c = self.0.each_ref().map(|x| to_f64(x, scale));
        // Scaled by the largest component so that neither the squares overflow nor underflow.
        let m = c.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if m == 0.0 {
            return 0.0;
        }
        m * c.iter().map(|x| (x / m) * (x / m)).sum::<f64>().sqrt()
    }
}

/// `v * 2^e` without overflowing or underflowing in the intermediate power of two.
pub fn scale2(mut v: f64, mut e: i64) -> f64 {
    while e > 1000 {
        v *= 2f64.powi(1000);
        e -= 1000;
    }
    while e < -1000 {
        v *= 2f64.powi(-1000);
        e += 1000;
    }
    v * 2f64.powi(e as i32)
}

/// `x / 2^scale`, rounded to `f64` (within about 2 ulps).
pub fn to_f64(x: &BigInt, scale: u32) -> f64 {
    let bits = x.bits();
    if bits <= 64 {
        return scale2(x.to_f64().unwrap_or(0.0), -(scale as i64));
    }
    let drop = bits - 64;
    // The magnitude is shifted, not the signed value: `>>` rounds negative values downwards.
    let m = (x.magnitude() >> drop).to_f64().unwrap_or(0.0);
    let v = scale2(m, drop as i64 - scale as i64);
    if x.sign() == Sign::Minus { -v } else { v }
}

/// `n / d` rounded to `f64` (within about 2 ulps); `d` non-zero.
pub fn ratio(n: &BigInt, d: &BigInt) -> f64 {
    if n.is_zero() {
        return 0.0;
    }
    // A quotient of 64 to 66 significant bits, then the power of two taken out again.
    let k = d.bits() as i64 - n.bits() as i64 + 64;
    let q = if k >= 0 {
        (n << k as u64) / d
    } else {
        n / (d << (-k) as u64)
    };
    scale2(q.to_f64().unwrap_or(0.0), -k)
}

/// The spacing of `f32` values at `|x|` (an `f64`, so also beyond the `f32` range): 2^-149
/// below the normal range, else `2^(floor(log2 |x|) - 23)`.
pub fn ulp_f32(x: f64) -> f64 {
    let x = x.abs();
    if !x.is_finite() {
        return f64::INFINITY;
    }
    if x < f32::MIN_POSITIVE as f64 {
        return scale2(1.0, -149);
    }
    let e = ((x.to_bits() >> 52) & 0x7ff) as i64 - 1023;
    scale2(1.0, e - 23)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_point_round_trips() {
        for x in [
            0.0f32,
            -0.0,
            1.0,
            -1.5,
            f32::MAX,
            f32::MIN_POSITIVE,
            f32::from_bits(1),
            1e-40,
            3.3e38,
        ] {
            assert_eq!(to_f64(&fix(x), FRAC), x as f64, "{x:e}");
        }
        assert_eq!(ratio(&fix(1.0), &fix(3.0)), 1.0 / 3.0);
        assert_eq!(ulp_f32(1.0), f32::EPSILON as f64);
        assert_eq!(ulp_f32(0.0), f32::from_bits(1) as f64);
    }
}
