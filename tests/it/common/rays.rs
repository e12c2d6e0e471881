//! Seeded ray generators. [`mixed`] cycles through every kind, so any slice of its output
//! exercises all of them: incoherent rays, rays aimed at primitives, axis-parallel rays along
//! box planes, finite segments, rays leaving surfaces, and segments ending exactly on a hit.

use super::{Rng, brute, closest, scene_box};
use lumis_core::accel::Accel;
use lumis_core::geometry::Geometry;
use lumis_core::math::{Aabb, Ray, Vec3};

/// The box `b` grown by `f` times its largest extent on every side.
pub fn grown(b: &Aabb, f: f32) -> Aabb {
    let m = Vec3::splat(b.extent().max_element().max(1e-3) * f);
    Aabb::new(b.min - m, b.max + m)
}

/// Random origin around the scene, random direction (sometimes not unit length: `t` is in
/// units of `dir`, and traversal must not assume otherwise).
pub fn incoherent(rng: &mut Rng, scene: &Aabb) -> Ray {
    let o = rng.in_box(&grown(scene, 0.2));
    let len = if rng.chance(0.25) {
        rng.range(0.1, 10.0)
    } else {
        1.0
    };
    Ray::new(o, rng.unit_vector() * len)
}

/// The centre of a random primitive's box (the scene centre when there are none).
fn target(rng: &mut Rng, g: &Geometry, bounds: &[Aabb]) -> Vec3 {
    if bounds.is_empty() {
        scene_box(g).center()
    } else {
        bounds[rng.below(bounds.len())].center()
    }
}

/// From a random origin around the scene towards a random primitive's centroid (`t = 1` there).
pub fn aimed(rng: &mut Rng, g: &Geometry, bounds: &[Aabb]) -> Ray {
    let o = rng.in_box(&grown(&scene_box(g), 0.3));
    let d = target(rng, g, bounds) - o;
    Ray::new(o, if d == Vec3::ZERO { Vec3::X } else { d })
}

/// Axis-parallel rays (one or two zero direction components) whose origin sits exactly on a
/// primitive's box planes or centre on the zero axes, so the slab test sees `0 * inf` cases.
pub fn axis_parallel(rng: &mut Rng, g: &Geometry, bounds: &[Aabb]) -> Ray {
    let scene = grown(&scene_box(g), 0.1);
    let b = if bounds.is_empty() {
        scene
    } else {
        bounds[rng.below(bounds.len())]
    };
    let mut o = rng.in_box(&scene);
    let mut d = Vec3::ZERO;
    let along = rng.below(3);
    // Two nonzero components half the time: the ray then lies in an axis-aligned plane.
    let second = if rng.chance(0.5) {
        Some((along + 1 + rng.below(2)) % 3)
    } else {
        None
    };
    for axis in 0..3 {
        if axis == along || Some(axis) == second {
            d[axis] = if rng.chance(0.5) { 1.0 } else { -1.0 } * rng.range(0.5, 2.0);
        } else {
            o[axis] = match rng.below(3) {
                0 => b.min[axis],
                1 => b.max[axis],
                _ => b.center()[axis],
            };
        }
    }
    Ray::new(o, d)
}

/// A segment towards a primitive ending somewhere between 0.2 and 1.2 of the way to its centroid.
pub fn segment(rng: &mut Rng, g: &Geometry, bounds: &[Aabb]) -> Ray {
    let mut r = aimed(rng, g, bounds);
    r.t_max = rng.range(0.2, 1.2);
    r
}

/// A ray leaving a surface point in a random direction, with no origin offset: the traversal
/// must handle hits at `t` near 0 exactly as brute force does.
pub fn from_surface(rng: &mut Rng, g: &Geometry, bounds: &[Aabb], reference: &Accel) -> Ray {
    let probe = aimed(rng, g, bounds);
    match closest(reference, g, &probe) {
        Some(h) => Ray::new(probe.at(h.hit.t), rng.unit_vector()),
        None => incoherent(rng, &scene_box(g)),
    }
}

/// A segment whose `t_max` is exactly the brute-force hit distance: a box entered at exactly
/// `t_max` must not be culled, or shadow rays to a surface point report a false "unblocked".
pub fn ending_on_hit(rng: &mut Rng, g: &Geometry, bounds: &[Aabb], reference: &Accel) -> Ray {
    let mut r = if rng.chance(0.5) {
        aimed(rng, g, bounds)
    } else {
        axis_parallel(rng, g, bounds)
    };
    if let Some(h) = closest(reference, g, &r) {
        r.t_max = h.hit.t;
    }
    r
}

/// `n` rays cycling through every generator above.
pub fn mixed(rng: &mut Rng, g: &Geometry, n: usize) -> Vec<Ray> {
    let bounds = g.prim_bounds();
    let reference = brute(g);
    let scene = scene_box(g);
    (0..n)
        .map(|i| match i % 6 {
            0 => incoherent(rng, &scene),
            1 => aimed(rng, g, &bounds),
            2 => axis_parallel(rng, g, &bounds),
            3 => segment(rng, g, &bounds),
            4 => from_surface(rng, g, &bounds, &reference),
            _ => ending_on_hit(rng, g, &bounds, &reference),
        })
        .collect()
}
