//! Failures the `queries` target's survey mode found (docs/robustness.md), each through the
//! whole checker, written with the exact `f32` bits it reported.

use super::queries::{self, Prim};
use super::{scene, sphere, tri};
use lumis_core::math::{Ray, Vec3};

fn v(bits: [u32; 3]) -> [f32; 3] {
    bits.map(f32::from_bits)
}

/// A sphere of radius 2^-69 grazed at its top by a ray from -5.9e22 whose interval ends
/// exactly there (`t_max = 1`): brute force counted the tangency-band hit (the line meets the
/// sphere's box), the BSP with one primitive per leaf did not visit it.
#[test]
fn a_far_ray_grazing_a_tiny_sphere_at_the_end_of_its_interval() {
    let (a, b, c) = (
        v([0, 0x3a80_0000, 0]),
        v([0x3a00_0000, 0x3b20_0000, 0]),
        v([0x0060_0004, 0x0000_0400, 0x0501_0402]),
    );
    let r = f32::from_bits;
    let prims: Vec<Prim> = vec![
        tri(a, b, c),
        tri(c, a, a),
        sphere(a, r(0x0403_0000)),
        sphere(c, r(0x1d00_0000)),
        tri(b, a, a),
        sphere(c, r(0x1b01_0000)),
        tri(c, a, b),
        tri(c, a, b),
    ];
    let ray = Ray {
        origin: Vec3::from(v([0xe546_af7b, 0x0b00_0079, 0x0b0b_0b0b])),
        dir: Vec3::from(v([0x6546_af7b, 0x1d00_0000, 0x8b0b_02fb])),
        t_min: r(0x3600_0000),
        t_max: 1.0,
    };
    queries::check(&scene(&prims), &[ray]);
}

/// A needle 2.7e14 long and 3e-4 wide, seen from beside its short edge along a direction of
/// 2.7e36 (its other components subnormal): the plane crossing is behind the origin
/// (t = -5.4e-41), but the compensated plane distance computed the edges `p - p0` in `f64`,
/// which rounded them (1.4e14 - 1.8e-4), tilted the normal and measured from the far vertex:
/// a false hit at t = 1.5e37 (found by the recorded 36-minute run, at its end).
#[test]
fn a_huge_needle_seen_from_beside_its_short_edge() {
    let (a, b, c) = (
        v([0x5701_0000, 0x5757_5757, 0x57]),
        v([0, 0, 0]),
        v([0xb940_0000, 0, 0x3980_0000]),
    );
    let prims: Vec<Prim> = vec![tri(a, b, a), tri(a, c, b)];
    let ray = Ray {
        origin: Vec3::from(v([0xb930_0000, 0x3780_0000, 0x38c0_0000])),
        dir: Vec3::from(v([0x2001, 4, 0xfc00_0400])),
        t_min: 0.0,
        t_max: f32::INFINITY,
    };
    queries::check(&scene(&prims), &[ray]);
}
