use super::*;

const UV: Vec2 = Vec2::ZERO;

/// Deterministic world points over a few hundred units, both signs.
fn points(n: usize) -> impl Iterator<Item = Vec3> {
    (0..n).map(|i| {
        let i = i as f32;
        Vec3::new(
            (i * 0.618_034).fract(),
            (i * 0.754_877_7).fract(),
            (i * 0.569_840_3).fract(),
        ) * 300.0
            - Vec3::splat(150.0)
    })
}

/// Every kind with primary colours, so the blend weights are easy to read off: two-colour kinds
/// blend X and Y, CrissCross blends X, Y and Z.
fn kinds(scale: f32) -> Vec<Texture> {
    let (a, b, c) = (Vec3::X, Vec3::Y, Vec3::Z);
    vec![
        Texture::Checkerboard {
            a,
            b,
            scale,
            origin: Vec3::ZERO,
        },
        Texture::Turbulence { a, b, scale },
        Texture::Marble { a, b, scale },
        Texture::Wood { a, b, scale },
        Texture::CrissCross { a, b, c, scale },
    ]
}

#[test]
fn solid_is_constant() {
    let t = Texture::Solid(Vec3::new(0.1, 0.2, 0.3));
    for p in points(10) {
        assert_eq!(t.eval(p, UV), Vec3::new(0.1, 0.2, 0.3));
    }
}

#[test]
fn checker_parity_at_known_points() {
    let (a, b) = (Vec3::ONE, Vec3::ZERO);
    let checker = |scale, origin| Texture::Checkerboard {
        a,
        b,
        scale,
        origin,
    };
    let t = checker(1.0, Vec3::ZERO);
    let at = |x: f32, y: f32, z: f32| t.eval(Vec3::new(x, y, z), UV);
    assert_eq!(at(0.5, 0.5, 0.5), a);
    assert_eq!(at(1.5, 0.5, 0.5), b);
    assert_eq!(at(1.5, 1.5, 0.5), a);
    assert_eq!(at(1.5, 1.5, 1.5), b);
    // floor(-0.5) = -1 is odd: no mirrored double-width cell at the origin.
    assert_eq!(at(-0.5, 0.5, 0.5), b);
    assert_eq!(at(-0.5, -0.5, 0.5), a);
    assert_eq!(at(-1.5, 0.5, 0.5), a);
    let big = checker(2.0, Vec3::ZERO);
    assert_eq!(big.eval(Vec3::new(1.5, 0.5, 0.5), UV), a);
    assert_eq!(big.eval(Vec3::new(2.5, 0.5, 0.5), UV), b);
    // The original's grid: cells of 50 counted from -3,893,343, i.e. edges at 7 mod 50 (in f64,
    // so the far corner does not round p). [7, 57) is cell 77,867 (odd) on each axis.
    let scn = checker(50.0, SCN_CHECKER_ORIGIN);
    assert_eq!(scn.eval(Vec3::splat(7.5), UV), b);
    assert_eq!(scn.eval(Vec3::splat(56.9), UV), b);
    assert_eq!(scn.eval(Vec3::new(6.9, 7.5, 7.5), UV), a);
    assert_eq!(scn.eval(Vec3::new(57.1, 7.5, 7.5), UV), a);
    // Points beyond the integer range must not panic.
    for p in [
        Vec3::new(1e30, -1e30, 3e38),
        Vec3::splat(f32::MAX),
        Vec3::splat(f32::NAN),
    ] {
        let c = t.eval(p, UV);
        assert!(c == a || c == b);
    }
}

#[test]
fn outputs_lie_where_the_originals_weights_put_them() {
    for t in kinds(7.0) {
        for p in points(5000) {
            let c = t.eval(p, UV);
            assert!(c.min_element() >= 0.0, "{t:?} at {p}: {c}");
            let sum = c.element_sum();
            match t {
                // In the convex hull of the two colours.
                Texture::Checkerboard { .. } | Texture::Marble { .. } => {
                    assert!((sum - 1.0).abs() < 1e-5 && c.z == 0.0, "{t:?} at {p}: {c}")
                }
                // A quarter of each of three blends: 3/4 of the hull of the three colours.
                Texture::CrissCross { .. } => {
                    assert!((sum - 0.75).abs() < 1e-5, "{t:?} at {p}: {c}")
                }
                // Past X (t > 1, Y's weight clamped at 0) but never below the hull.
                Texture::Turbulence { .. } => {
                    assert!(
                        sum >= 1.0 - 1e-5 && c.x < 2.0 && c.z == 0.0,
                        "{t:?} at {p}: {c}"
                    )
                }
                // t in (-1, 1): past Y (X's weight clamped at 0) where the noise is negative.
                Texture::Wood { .. } => {
                    assert!(
                        sum >= 1.0 - 1e-5 && c.y < 2.0 && c.z == 0.0,
                        "{t:?} at {p}: {c}"
                    )
                }
                _ => unreachable!(),
            }
        }
    }
}

#[test]
fn turbulence_and_wood_extrapolate_as_the_original() {
    let (a, b, scale) = (Vec3::X, Vec3::Y, 7.0);
    let turb = Texture::Turbulence { a, b, scale };
    let past_a = points(5000).filter(|p| turb.eval(*p, UV).x > 1.0).count();
    // The harmonic sum exceeds 1 now and then (about 0.6 on average).
    assert!(
        (5..1000).contains(&past_a),
        "turbulence past a at {past_a} points"
    );
    let wood = Texture::Wood { a, b, scale };
    // Truncation: where the noise is negative the weight is negative, so about half the
    // surface lies past b (Y above 1), the broad bright rings of the original's wood.
    let past_b = points(5000).filter(|p| wood.eval(*p, UV).y > 1.0).count();
    assert!(
        (1500..3500).contains(&past_b),
        "wood past b at {past_b} points"
    );
}

#[test]
fn scale_invariance() {
    // Powers of two divide exactly, so the noise sees the very same point.
    for s in [0.25f32, 4.0] {
        for (scaled, unit) in kinds(s).iter().zip(kinds(1.0)) {
            for p in points(500).map(|p| p * 0.05) {
                let d = (scaled.eval(p * s, UV) - unit.eval(p, UV))
                    .abs()
                    .max_element();
                assert!(d <= 1e-5, "{unit:?} scale {s} at {p}: {d}");
            }
        }
    }
    // Any other factor only rounds: smooth kinds agree closely.
    let s = 3.7;
    for (scaled, unit) in kinds(s).iter().zip(kinds(1.0)).skip(1).take(2) {
        for p in points(500).map(|p| p * 0.05) {
            let d = (scaled.eval(p * s, UV) - unit.eval(p, UV))
                .abs()
                .max_element();
            assert!(d <= 1e-3, "{unit:?} scale {s} at {p}: {d}");
        }
    }
}

#[test]
fn known_values_on_the_noise_lattice() {
    // At q = p / scale on the integer lattice every noise lookup is 0.
    let (a, b, c) = (
        Vec3::new(0.9, 0.1, 0.2),
        Vec3::new(0.1, 0.3, 0.7),
        Vec3::new(0.5, 0.5, 0.0),
    );
    let s = 2.0;
    let p = Vec3::new(4.0, -6.0, 10.0); // q = (2, -3, 5)
    assert_eq!(Texture::Turbulence { a, b, scale: s }.eval(p, UV), b);
    assert_eq!(Texture::Wood { a, b, scale: s }.eval(p, UV), b);
    // Marble: t = 0.5 + 0.5 sin(q.x + q.y) = 0.5 + 0.5 sin(-1).
    let t = 0.5 + 0.5 * (-1.0f32).sin();
    let m = Texture::Marble { a, b, scale: s }.eval(p, UV);
    assert!((m - (b + (a - b) * t)).abs().max_element() < 1e-6);
    // CrissCross at the origin: every band is at sin(0), t = 0.5, so each blend is the mean
    // of its pair and the quarter weights give (a + b + c) / 4.
    let cc = Texture::CrissCross { a, b, c, scale: s }.eval(Vec3::ZERO, UV);
    assert!((cc - (a + b + c) / 4.0).abs().max_element() < 1e-6);
}

/// Mean and spread of a two-colour texture's blend weight `t`, read back from colours chosen
/// so that no weight in (-1, 2) meets the clamp at 0: `b + t (a - b) = (1 + t, 2 - t, 0)`.
fn weight_stats(t: &Texture) -> (f32, f32) {
    let w: Vec<f32> = points(20_000).map(|p| t.eval(p, UV).x - 1.0).collect();
    let mean = w.iter().sum::<f32>() / w.len() as f32;
    let var = w.iter().map(|x| (x - mean).powi(2)).sum::<f32>() / w.len() as f32;
    (mean, var.sqrt())
}

#[test]
fn patterns_vary_and_use_both_colours() {
    let (a, b, scale) = (Vec3::new(2.0, 1.0, 0.0), Vec3::new(1.0, 2.0, 0.0), 5.0);
    // Turbulence sits mostly mid-range; marble veins cover the sine's range; wood's sawtooth is
    // spread over (-1, 1), symmetric about 0 as the noise is.
    let (m, sd) = weight_stats(&Texture::Turbulence { a, b, scale });
    assert!((0.3..0.9).contains(&m) && sd > 0.08, "turbulence {m} {sd}");
    let (m, sd) = weight_stats(&Texture::Marble { a, b, scale });
    assert!((0.3..0.7).contains(&m) && sd > 0.25, "marble {m} {sd}");
    let (m, sd) = weight_stats(&Texture::Wood { a, b, scale });
    assert!(m.abs() < 0.1 && sd > 0.3, "wood {m} {sd}");
}

#[test]
fn smooth_kinds_are_continuous() {
    for t in kinds(3.0)
        .iter()
        .skip(1)
        .filter(|t| !matches!(t, Texture::Wood { .. }))
    {
        for p in points(2000) {
            let d = (t.eval(p + Vec3::splat(1e-4), UV) - t.eval(p, UV))
                .abs()
                .max_element();
            assert!(d < 0.01, "{t:?} jumps {d} at {p}");
        }
    }
}

#[test]
fn is_black_only_when_every_colour_is() {
    let k = Vec3::ZERO;
    assert!(Texture::Solid(k).is_black());
    assert!(!Texture::Solid(Vec3::X).is_black());
    assert!(
        Texture::Marble {
            a: k,
            b: k,
            scale: 1.0
        }
        .is_black()
    );
    assert!(
        !Texture::Wood {
            a: k,
            b: Vec3::X,
            scale: 1.0
        }
        .is_black()
    );
    assert!(
        !Texture::Checkerboard {
            a: Vec3::X,
            b: k,
            scale: 1.0,
            origin: Vec3::ZERO
        }
        .is_black()
    );
    assert!(
        Texture::CrissCross {
            a: k,
            b: k,
            c: k,
            scale: 1.0
        }
        .is_black()
    );
    assert!(
        !Texture::CrissCross {
            a: k,
            b: k,
            c: Vec3::Z,
            scale: 1.0
        }
        .is_black()
    );
}

#[test]
fn validate_rejects_bad_scales() {
    for t in kinds(1.0) {
        assert!(t.validate().is_ok());
    }
    for s in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        for t in kinds(s) {
            assert!(t.validate().is_err(), "{t:?}");
        }
    }
    assert!(Texture::Solid(Vec3::splat(f32::NAN)).validate().is_err());
}

/// The paper's ray tracer's turbulence sum at `f` times the point, per-axis factors `k`.
fn scn_sum(p: Vec3, f: f32, k: Vec3) -> f32 {
    (1..=9)
        .map(|l| noise(p * f * k * l as f32).abs() / l as f32)
        .sum()
}

#[test]
fn scn_scale_conversion_reproduces_the_original_formulas() {
    let (a, b, c) = (Vec3::X, Vec3::Y, Vec3::Z);
    let close = |x: Vec3, y: Vec3, what: &str| {
        assert!((x - y).abs().max_element() < 2e-4, "{what}: {x} vs {y}")
    };
    for p in points(300) {
        let s = 0.75;
        // No clamp of the weight; only the colour is kept non-negative.
        let t = scn_sum(p, 0.05 * s, Vec3::ONE);
        close(
            Texture::Turbulence { a, b, scale: s }
                .from_scn_scale()
                .eval(p, UV),
            (b + (a - b) * t).max(Vec3::ZERO),
            "turbulence",
        );

        let s = 0.5;
        let x = p * s;
        let t =
            0.5 * ((x.x + x.y) * 0.05 + scn_sum(p, 0.05 * s, Vec3::new(1.0, 3.0, 1.0))).sin() + 0.5;
        close(
            Texture::Marble { a, b, scale: s }
                .from_scn_scale()
                .eval(p, UV),
            b + (a - b) * t,
            "marble",
        );

        let s = 0.01;
        // The original's `grain - (int)grain`: truncation towards zero.
        let g = noise(p * s) * 5.0;
        let t = g - g.trunc();
        // Right at a ring edge rounding may put the two on opposite sides of the jump.
        if (0.001..0.999).contains(&t.abs()) {
            close(
                Texture::Wood { a, b, scale: s }
                    .from_scn_scale()
                    .eval(p, UV),
                (b + (a - b) * t).max(Vec3::ZERO),
                "wood",
            );
        }

        let s = 0.1;
        let x = p * s * 0.5;
        let f = 0.5 * s;
        let ta = 0.5 * ((x.x + x.z) * 0.05 + scn_sum(p, f, Vec3::new(0.35, 0.05, 1.0))).sin() + 0.5;
        let tb = 0.5 * ((x.y + x.x) * 0.05 + scn_sum(p, f, Vec3::new(1.0, 0.35, 0.05))).sin() + 0.5;
        let tc = 0.5 * ((x.z + x.y) * 0.05 + scn_sum(p, f, Vec3::new(0.05, 1.0, 0.35))).sin() + 0.5;
        let want = (b + (a - b) * ta + c + (b - c) * tb + a + (c - a) * tc) * 0.25;
        close(
            Texture::CrissCross { a, b, c, scale: s }
                .from_scn_scale()
                .eval(p, UV),
            want,
            "crisscross",
        );
    }
    // The checker keeps its cell size and gets the original's grid corner.
    assert_eq!(
        Texture::Checkerboard {
            a,
            b,
            scale: 50.0,
            origin: Vec3::ZERO
        }
        .from_scn_scale(),
        Texture::Checkerboard {
            a,
            b,
            scale: 50.0,
            origin: SCN_CHECKER_ORIGIN
        }
    );
}

#[test]
fn image_texture_reads_uv_times_tint_and_ignores_p() {
    let img = ImageTexture::new(2, 1, vec![Vec3::X, Vec3::Y]).unwrap();
    let t = Texture::Image {
        image: std::sync::Arc::new(img),
        tint: Vec3::splat(0.5),
    };
    assert_eq!(
        t.eval(Vec3::splat(7.0), Vec2::new(0.25, 0.5)),
        Vec3::X * 0.5
    );
    assert_eq!(t.eval(Vec3::ZERO, Vec2::new(0.75, 0.5)), Vec3::Y * 0.5);
    assert!(!t.is_black() && t.validate().is_ok() && t.scale().is_none());
    assert_eq!(t.clone().from_scn_scale(), t);
}
