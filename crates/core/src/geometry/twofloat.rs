//! Double-double ("two-float") arithmetic: an unevaluated sum `hi + lo` of two `f64`s with
//! `|lo| <= ulp(hi) / 2`, about 106 significant bits.
//!
//! Built from the error-free transforms of Dekker and Knuth (`two_sum`, `two_prod` via fused
//! multiply-add): the rounding error of one `f64` addition or product is itself an `f64`, so it
//! can be carried instead of dropped. Used by the sphere intersector where `|f|^2 - r^2` and the
//! discriminant cancel catastrophically even in `f64` (huge spheres, grazing rays, origins on the
//! surface). Every sum or difference of two `f32`s, and every product of two `f64`s, is exact as
//! a [`Dd`]; the arithmetic operators have a relative error of a few `2^-106`.

/// `hi + lo` exactly, with `hi = fl(a + b)` (Knuth's branch-free two-sum).
#[inline]
pub fn two_sum(a: f64, b: f64) -> Dd {
    let hi = a + b;
    let bb = hi - a;
    let lo = (a - (hi - bb)) + (b - bb);
    Dd { hi, lo }
}

/// `hi + lo == a + b` exactly when `|a| >= |b|` (or `a == 0`): three flops instead of six.
#[inline]
fn fast_two_sum(a: f64, b: f64) -> Dd {
    let hi = a + b;
    Dd {
        hi,
        lo: b - (hi - a),
    }
}

/// `hi + lo == a * b` exactly (barring underflow below 2^-969), `hi = fl(a * b)`.
#[inline]
pub fn two_prod(a: f64, b: f64) -> Dd {
    let hi = a * b;
    Dd {
        hi,
        lo: a.mul_add(b, -hi),
    }
}

/// A double-double number `hi + lo`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dd {
    /// The leading part: the value rounded to `f64`.
    pub hi: f64,
    /// The trailing part, `|lo| <= ulp(hi) / 2`.
    pub lo: f64,
}

impl Dd {
    /// `(hi, lo)`, for code that carries the parts separately (expansions, compensated sums).
    #[inline]
    pub fn parts(self) -> (f64, f64) {
        (self.hi, self.lo)
    }

    /// Zero.
    pub const ZERO: Dd = Dd { hi: 0.0, lo: 0.0 };

    /// An exact `f64`.
    #[inline]
    pub fn from_f64(x: f64) -> Self {
        Dd { hi: x, lo: 0.0 }
    }

    /// The value rounded to `f64` (`hi + lo` rounds correctly since `lo` is below half an ulp).
    #[inline]
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    /// The value rounded to the nearest `f32`. Rounding `hi` alone is right except when `hi` is
    /// exactly halfway between two `f32`s: then the sign of `lo` breaks the tie.
    #[inline]
    pub fn to_f32(self) -> f32 {
        let r = self.hi as f32;
        // Exact: `hi` and `r` are within half an f32 ulp of each other.
        let d = self.hi - r as f64;
        if d == 0.0 || self.lo == 0.0 || !r.is_finite() {
            return r;
        }
        let other = if d > 0.0 { r.next_up() } else { r.next_down() };
        let tie = other as f64 - self.hi == d;
        if tie && (self.lo > 0.0) == (d > 0.0) && other.is_finite() {
            other
        } else {
            r
        }
    }

    /// `self + b`.
    #[inline]
    pub fn add(self, b: Dd) -> Dd {
        // Accurate (Shewchuk/Bailey "IEEE") addition: both error terms are kept.
        let s = two_sum(self.hi, b.hi);
        let t = two_sum(self.lo, b.lo);
        let s = fast_two_sum(s.hi, s.lo + t.hi);
        fast_two_sum(s.hi, s.lo + t.lo)
    }

    /// `self + b` for an `f64`.
    #[inline]
    pub fn add_f64(self, b: f64) -> Dd {
        let s = two_sum(self.hi, b);
        fast_two_sum(s.hi, s.lo + self.lo)
    }

    /// `-self`.
    #[inline]
    pub fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }

    /// `self - b`.
    #[inline]
    pub fn sub(self, b: Dd) -> Dd {
        self.add(b.neg())
    }

    /// `self * b`.
    #[inline]
    pub fn mul(self, b: Dd) -> Dd {
        let p = two_prod(self.hi, b.hi);
        let lo = p.lo + (self.hi * b.lo + self.lo * b.hi);
        fast_two_sum(p.hi, lo)
    }

    /// `self * b` for an `f64`.
    #[inline]
    pub fn mul_f64(self, b: f64) -> Dd {
        let p = two_prod(self.hi, b);
        fast_two_sum(p.hi, p.lo + self.lo * b)
    }

    /// `self^2`.
    #[inline]
    pub fn square(self) -> Dd {
        self.mul(self)
    }

    /// `self / b`: one Newton correction of the `f64` quotient.
    #[inline]
    pub fn div(self, b: Dd) -> Dd {
        let q1 = self.hi / b.hi;
        let r = self.sub(b.mul_f64(q1));
        let q2 = r.hi / b.hi;
        let r = r.sub(b.mul_f64(q2));
        let q3 = r.hi / b.hi;
        fast_two_sum(q1, q2).add_f64(q3)
    }

    /// `sqrt(self)` for `self >= 0` (0 for negative input): one Newton step from the `f64` root.
    #[inline]
    pub fn sqrt(self) -> Dd {
        if self.hi <= 0.0 {
            return Dd::ZERO;
        }
        let s = self.hi.sqrt();
        let r = self.sub(two_prod(s, s));
        fast_two_sum(s, r.hi / (2.0 * s))
    }

    /// True when the value is below zero.
    #[inline]
    pub fn is_negative(self) -> bool {
        self.hi < 0.0 || (self.hi == 0.0 && self.lo < 0.0)
    }
}

/// `a - b` exactly for `f32` inputs (the difference of two `f32`s always fits in a [`Dd`]).
#[inline]
pub fn diff_f32(a: f32, b: f32) -> Dd {
    two_sum(a as f64, -(b as f64))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_free_transforms_are_exact() {
        let s = two_sum(1e16, 1.0);
        assert_eq!((s.hi, s.lo), (1e16, 1.0));
        // 1e7 + 1e-4 needs 77 bits: hi holds the rounded sum, lo the exact rest.
        let d = diff_f32(1e-4, -1e7);
        assert_eq!((d.hi - 1e7) + d.lo, 1e-4f32 as f64);
        let p = two_prod(1.0 + 2f64.powi(-30), 1.0 + 2f64.powi(-30));
        assert_eq!((p.hi, p.lo), (1.0 + 2f64.powi(-29), 2f64.powi(-60)));
    }

    #[test]
    fn arithmetic_keeps_about_106_bits() {
        let third = Dd::from_f64(1.0).div(Dd::from_f64(3.0));
        let back = third.mul_f64(3.0).sub(Dd::from_f64(1.0));
        assert!(back.to_f64().abs() < 1e-31, "{back:?}");
        let two = Dd::from_f64(2.0).sqrt();
        let err = two.square().sub(Dd::from_f64(2.0));
        assert!(err.to_f64().abs() < 1e-31, "{err:?}");
        // (1e8 + 1e-9)^2 - 1e16 = 0.2 + 1e-18 needs more than f64.
        let x = two_sum(1e8, 1e-9);
        let v = x.square().add_f64(-1e16).to_f64();
        assert!((v - 0.2).abs() < 1e-16, "{v}");
    }

    #[test]
    fn rounds_to_the_nearest_f32_without_double_rounding() {
        // hi exactly halfway between 1 and 1 + 2^-23; lo decides.
        let tie = 1.0 + 2f64.powi(-24);
        assert_eq!(Dd { hi: tie, lo: 1e-30 }.to_f32(), 1.0 + f32::EPSILON);
        assert_eq!(
            Dd {
                hi: tie,
                lo: -1e-30
            }
            .to_f32(),
            1.0
        );
        assert_eq!(Dd::from_f64(-2.5).to_f32(), -2.5);
    }
}
