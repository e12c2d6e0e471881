//! The spheres of the cross-check: the exact discriminant, the footprint's distance from the
//! centre, and roots bracketed exactly.

use super::{Exact, LOOSE, ROOT_TOL, Seen, cmp_signed_sqrt};
use crate::query_fuzz::exact::{Q, V, exact_to_f64, q, q64};
use crate::query_fuzz::queries::oracle::Class;
use lumis_core::math::Vec3;
use num_traits::{Signed, Zero};
use std::cmp::Ordering::{self, Equal, Greater, Less};

/// The order of `t` against the lower (`upper` false) or upper root of `a t^2 + 2 b t + c`,
/// `disc = b^2 - a c >= 0`, `a > 0`: the sign of `(a t + b) -+ sqrt(disc)`, exactly.
fn cmp_root(t: &Q, a: &Q, b: &Q, disc: &Q, upper: bool) -> Ordering {
    let y = a * t + b;
    let sign = match (disc.is_zero(), upper) {
        (true, _) => Equal,
        (false, true) => Less,
        (false, false) => Greater,
    };
    // y + sign sqrt(disc) against 0 is sign sqrt(disc) against -y.
    cmp_signed_sqrt(sign, disc, &-y)
}

pub(super) fn sphere(
    x: &Exact,
    center: Vec3,
    radius: f32,
    class: Class,
    seen: &mut Seen,
) -> Result<(), String> {
    let f = x.o.sub(&V::of(center));
    let (a, b) = (&x.dd, f.dot(&x.d));
    let r = q(radius);
    let r2 = &r * &r;
    let disc = &b * &b - a * (f.dot(&f) - &r2);
    // The footprint: the closest approach's distance from the centre, squared.
    let foot = f.add(&x.d.scale(&(-&b / a)));
    let h2 = foot.dot(&foot);
    ensure!(
        disc == a * (&r2 - &h2),
        "the exact arithmetic: disc != a (r^2 - h^2)"
    );
    // `t` in [lo, hi] holds the root.
    let brackets = |lo: &Q, hi: &Q, upper: bool| {
        cmp_root(lo, a, &b, &disc, upper) != Greater && cmp_root(hi, a, &b, &disc, upper) != Less
    };
    match class {
        Class::Hit(roots) => {
            let inner = &r - &x.delta;
            ensure!(
                inner.is_positive() && h2 < &inner * &inner,
                "clear hit, but the footprint is not delta inside the rim (h / r = {:e})",
                exact_to_f64(&(&h2 / &r2)).sqrt()
            );
            ensure!(
                disc.is_positive(),
                "clear hit, but no positive discriminant"
            );
            ensure!(
                roots.len() == 2 && roots[0].t <= roots[1].t,
                "roots {roots:?}"
            );
            let half = (roots[1].dt - roots[0].dt) / 2.0;
            for (root, upper) in roots.iter().zip([false, true]) {
                let bracket = |tol: f64| {
                    let e = q64(tol * root.t.abs());
                    brackets(&(q64(root.t) - &e), &(q64(root.t) + &e), upper)
                };
                let err = (0..=22)
                    .map(|k| 2f64.powi(k - 52))
                    .find(|&tol| bracket(tol));
                seen.root = seen.root.max(err.unwrap_or(f64::INFINITY));
                ensure!(bracket(ROOT_TOL), "root {:e} not the exact one", root.t);
                let e = q64(ROOT_TOL * (root.dt.abs() + half));
                let dt = q64(root.dt) + &x.t_ref;
                ensure!(
                    brackets(&(&dt - &e), &(&dt + &e), upper),
                    "root {:e}: its offset {:e} is not the exact one",
                    root.t,
                    root.dt
                );
            }
            seen.count("sphere: clear hit");
        }
        Class::Miss => {
            let outer = &r + &x.delta;
            ensure!(
                h2 > &outer * &outer,
                "clear miss, but the footprint is within delta of the rim (h / r = {:e})",
                exact_to_f64(&(&h2 / &r2)).sqrt()
            );
            ensure!(
                disc.is_negative(),
                "clear miss, but no negative discriminant"
            );
            seen.count("sphere: clear miss");
        }
        Class::Ambiguous { lo, hi, dt_lo } => {
            let loose = &x.delta * q64(LOOSE);
            let (outer, inner) = (&r + &loose, &r - &loose);
            ensure!(
                h2 <= &outer * &outer && (!inner.is_positive() || h2 >= &inner * &inner),
                "ambiguous, but the footprint is not within delta of the rim (h / r = {:e})",
                exact_to_f64(&(&h2 / &r2)).sqrt()
            );
            if !disc.is_negative() {
                let (lo, hi) = (q64(lo), q64(hi));
                ensure!(
                    cmp_root(&lo, a, &b, &disc, false) != Greater
                        && cmp_root(&hi, a, &b, &disc, true) != Less,
                    "ambiguous over [{lo}, {hi}], but an exact root lies outside"
                );
                let first = q64(dt_lo) + &x.t_ref;
                ensure!(
                    cmp_root(&first, a, &b, &disc, false) != Greater,
                    "earliest offset {dt_lo:e} beyond the exact lower root's"
                );
            }
            seen.count(match disc.cmp(&Q::zero()) {
                Less => "sphere: ambiguous, an exact miss",
                Equal => "sphere: ambiguous, exactly tangent",
                Greater => "sphere: ambiguous, an exact hit",
            });
        }
    }
    Ok(())
}
