//! The triangles of the cross-check: Cramer's rule with exact barycentrics, and the line
//! against the plane and the box of a triangle it does not cross at one point.

use super::{DIST_TOL, Exact, LOOSE, RATIO_TOL, Seen, close, cmp_signed_sqrt};
use crate::query_fuzz::exact::{Q, V, exact_to_f64, q64, ray_triangle};
use crate::query_fuzz::queries::oracle::{Class, Crossing};
use lumis_core::math::{Aabb, Vec3};
use num_traits::{One, Signed, Zero};
use std::cmp::Ordering::{self, Greater, Less};

pub(super) fn triangle(
    x: &Exact,
    c: [Vec3; 3],
    class: Class,
    crossing: Option<Crossing>,
    seen: &mut Seen,
) -> Result<(), String> {
    let p = c.map(V::of);
    let (e1, e2) = (p[1].sub(&p[0]), p[2].sub(&p[0]));
    let n = e1.cross(&e2);
    let nd = n.dot(&x.d);
    if nd.is_zero() {
        return flat_triangle(x, c, &n, class, crossing, seen);
    }
    let Some(crossing) = crossing else {
        return Err("no crossing reported, but the line crosses the plane".into());
    };
    // Cramer's rule on u e1 + v e2 - t d = o - p0.
    let (s, md) = (x.o.sub(&p[0]), V(x.d.0.clone().map(|v| -v)));
    let det = e1.dot(&e2.cross(&md));
    let u = s.dot(&e2.cross(&md)) / &det;
    let v = e1.dot(&s.cross(&md)) / &det;
    let t = e1.dot(&e2.cross(&s)) / &det;
    let w = [Q::one() - &u - &v, u, v];
    let root = crossing.root;
    ensure!(
        close(root.t, &t, RATIO_TOL),
        "plane crossing t = {:e}, exactly {:e}",
        root.t,
        exact_to_f64(&t)
    );
    if !t.is_zero() {
        let err = exact_to_f64(&((q64(root.t) - &t) / &t)).abs();
        seen.plane_t = seen.plane_t.max(err);
    }
    let dt = &t - &x.t_ref;
    ensure!(
        close(root.dt, &dt, RATIO_TOL),
        "crossing offset {:e}, exactly {:e}",
        root.dt,
        exact_to_f64(&dt)
    );
    // The displaced line's crossing moves by at most delta |n| / |n.d| in t.
    let (shift, nd2) = (q64(root.shift), &nd * &nd);
    ensure!(
        &shift * &shift * &nd2 >= &x.delta * &x.delta * n.dot(&n) * q64(1.0 - 1e-12),
        "crossing shift {:e} below delta |n| / |n.d|",
        root.shift
    );
    // The signed distance from edge k (opposite corner k) as a sign and a square.
    let dist: Vec<(Ordering, Q)> = (0..3)
        .map(|k| {
            let side = p[(k + 2) % 3].sub(&p[(k + 1) % 3]).cross(&x.d);
            (w[k].cmp(&Q::zero()), &w[k] * &w[k] * &nd2 / side.dot(&side))
        })
        .collect();
    for (k, (sign, sq)) in dist.iter().enumerate() {
        let o = crossing.dist[k];
        let (a, b) = (o * (1.0 - DIST_TOL), o * (1.0 + DIST_TOL));
        let (lo, hi) = (q64(a.min(b)), q64(a.max(b)));
        ensure!(
            cmp_signed_sqrt(*sign, sq, &lo) != Less && cmp_signed_sqrt(*sign, sq, &hi) != Greater,
            "edge {k}: the oracle's distance {o:e}, exactly {}{:e}",
            if *sign == Less { "-" } else { "" },
            exact_to_f64(sq).sqrt()
        );
    }
    let cmp = |m: &Q| {
        dist.iter()
            .map(|(s, sq)| cmp_signed_sqrt(*s, sq, m))
            .collect::<Vec<_>>()
    };
    let w_f = || w.each_ref().map(exact_to_f64);
    let hit = ray_triangle(x.ray.origin, x.ray.dir, c);
    let inside = w.iter().all(|w| !w.is_negative());
    ensure!(inside == hit.is_some(), "Cramer and ray_triangle disagree");
    match class {
        Class::Hit(roots) => {
            ensure!(
                cmp(&x.delta).iter().all(|o| *o == Greater),
                "clear hit, but within delta of an edge (w = {:?})",
                w_f()
            );
            ensure!(
                hit.is_some_and(|h| !h.on_boundary()),
                "clear hit, but not strictly inside by ray_triangle"
            );
            ensure!(roots.len() == 1 && roots[0].t == root.t, "roots {roots:?}");
            seen.count("triangle: clear hit");
        }
        Class::Miss => {
            ensure!(
                cmp(&-&x.delta).contains(&Less),
                "clear miss, but within delta of every edge (w = {:?})",
                w_f()
            );
            ensure!(hit.is_none(), "clear miss, but an exact hit");
            seen.count("triangle: clear miss");
        }
        Class::Ambiguous { lo, hi, dt_lo } => {
            let loose = &x.delta * q64(LOOSE);
            ensure!(
                !cmp(&-&loose).contains(&Less) && cmp(&loose).iter().any(|o| *o != Greater),
                "ambiguous, but more than delta from an edge or inside all (w = {:?})",
                w_f()
            );
            let pad = q64(RATIO_TOL) * t.abs();
            ensure!(
                q64(lo) - &pad <= t && t <= q64(hi) + &pad,
                "ambiguous over [{lo:e}, {hi:e}], the exact t = {:e} outside",
                exact_to_f64(&t)
            );
            let pad = q64(RATIO_TOL) * dt.abs();
            ensure!(
                q64(dt_lo) <= &dt + pad,
                "earliest offset {dt_lo:e} beyond the exact one {:e}",
                exact_to_f64(&dt)
            );
            seen.count(match hit {
                Some(_) => "triangle: ambiguous, an exact hit",
                None => "triangle: ambiguous, an exact miss",
            });
        }
    }
    Ok(())
}

/// A triangle the line does not cross at one point: collinear corners (`n = 0`) or a plane
/// parallel to the ray.
fn flat_triangle(
    x: &Exact,
    c: [Vec3; 3],
    n: &V,
    class: Class,
    crossing: Option<Crossing>,
    seen: &mut Seen,
) -> Result<(), String> {
    let kind = if n.is_zero() {
        "degenerate"
    } else {
        "parallel"
    };
    ensure!(crossing.is_none(), "{kind} triangle: a crossing reported");
    // More than m off the plane: (n . (o - p0))^2 > m^2 |n|^2 (never for n = 0).
    let gap = n.dot(&x.o.sub(&V::of(c[0])));
    let off = |m: &Q| &gap * &gap > m * m * n.dot(n);
    let b = Aabb::from_points(c);
    let grow = |v: Vec3, by: &Q| V(V::of(v).0.map(|c| c + by));
    let near = slab(x, &grow(b.min, &-&x.delta), &grow(b.max, &x.delta));
    match class {
        Class::Hit(_) => return Err(format!("{kind} triangle: a clear hit")),
        Class::Miss => {
            ensure!(
                off(&x.delta) || near.is_none(),
                "{kind} triangle: a clear miss, but the exact line is within delta of its plane \
                 and its box"
            );
            seen.count(&format!("{kind} triangle: clear miss"));
        }
        Class::Ambiguous { lo, hi, .. } => {
            ensure!(
                !off(&(&x.delta * q64(LOOSE))),
                "{kind} triangle: ambiguous, but more than delta off its plane"
            );
            if let Some((t0, t1)) = &near {
                ensure!(
                    &q64(lo) <= t0 && t1 <= &q64(hi),
                    "{kind} triangle: ambiguous over [{lo:e}, {hi:e}], but the line is within \
                     delta of its box over [{:e}, {:e}]",
                    exact_to_f64(t0),
                    exact_to_f64(t1)
                );
            }
            seen.count(&format!("{kind} triangle: ambiguous"));
        }
    }
    Ok(())
}

/// The interval of `t` where the exact line lies in the box `[lo, hi]`, if it meets it.
fn slab(x: &Exact, lo: &V, hi: &V) -> Option<(Q, Q)> {
    let (mut t0, mut t1): (Option<Q>, Option<Q>) = (None, None);
    for i in 0..3 {
        let (o, d) = (&x.o.0[i], &x.d.0[i]);
        if d.is_zero() {
            if o < &lo.0[i] || o > &hi.0[i] {
                return None;
            }
            continue;
        }
        let (a, b) = ((&lo.0[i] - o) / d, (&hi.0[i] - o) / d);
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        t0 = Some(t0.map_or(a.clone(), |t| t.max(a)));
        t1 = Some(t1.map_or(b.clone(), |t| t.min(b)));
    }
    let (t0, t1) = (t0?, t1?);
    (t0 <= t1).then_some((t0, t1))
}
