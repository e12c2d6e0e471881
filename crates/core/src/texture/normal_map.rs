//! Bump-like shading-normal perturbation by 3-D noise (the `.scn` `NormalMap scale amount`).

use super::perlin::noise_rotations;
use crate::math::Vec3;

/// Perturbs shading normals by a smooth 3-D noise vector field in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalMap {
    /// Size of the bumps: world units per noise cell (the `.scn` value as is); must be > 0.
    pub scale: f32,
    /// Strength: the noise vector (components roughly in [-1, 1]) is multiplied by this before
    /// being added to the unit normal; 0 leaves normals unchanged.
    pub amount: f32,
}

impl NormalMap {
    /// The unit normal `n` at world point `p` bent by `amount` times a noise vector sampled at
    /// `q = p / scale`, renormalised. As in the original, the three components are the one
    /// noise at `q` with its coordinates rotated, `(noise(x, y, z), noise(y, z, x),
    /// noise(z, x, y))`: along the diagonal x = y = z they coincide and the bend is along
    /// (1, 1, 1). Returns `n` where the bent vector vanishes. The result may face
    /// away from the geometric normal for large `amount`; callers keep the side (see
    /// [`crate::material::Material::shading_normal`]).
    pub fn perturb(&self, n: Vec3, p: Vec3) -> Vec3 {
        let q = p / self.scale;
        // Rotating the coordinates reads the field along other axes: away from the diagonal
        // the three lookups are practically independent.
        let d = noise_rotations(q);
        (n + d * self.amount).try_normalize().unwrap_or(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::perlin::noise;

    #[test]
    fn zero_amount_is_identity_and_results_are_unit() {
        let n = Vec3::new(0.0, 0.6, 0.8);
        let p = Vec3::new(1.7, -3.2, 9.1);
        assert_eq!(
            NormalMap {
                scale: 0.5,
                amount: 0.0
            }
            .perturb(n, p),
            n
        );
        let bent = NormalMap {
            scale: 0.5,
            amount: 0.25,
        }
        .perturb(n, p);
        assert!((bent.length() - 1.0).abs() < 1e-5);
        assert!(bent != n);
        // |noise| <= ~1.04 per component bounds the tilt: |d * amount| <= 0.25 * 1.04 * sqrt 3
        // = 0.45, so at most asin(0.45) = 27 degrees, cos = 0.89.
        assert!(bent.dot(n) > 0.85);
    }

    #[test]
    fn smooth_in_p_and_scale_invariant() {
        let nm = NormalMap {
            scale: 2.0,
            amount: 0.5,
        };
        let n = Vec3::Z;
        let p = Vec3::new(0.3, 4.1, -2.2);
        let step = nm.perturb(n, p + Vec3::splat(1e-3)) - nm.perturb(n, p);
        assert!(step.length() < 5e-3);
        let unit = NormalMap {
            scale: 1.0,
            amount: 0.5,
        };
        assert!((nm.perturb(n, p * 2.0) - unit.perturb(n, p)).length() < 1e-5);
    }

    #[test]
    fn components_are_the_noise_with_rotated_coordinates() {
        let nm = NormalMap {
            scale: 0.5,
            amount: 1.0,
        };
        let p = Vec3::new(0.7, -1.3, 2.9);
        let q = p / 0.5;
        let d = nm.perturb(Vec3::ZERO, p);
        let want = Vec3::new(
            noise(q),
            noise(Vec3::new(q.y, q.z, q.x)),
            noise(Vec3::new(q.z, q.x, q.y)),
        )
        .normalize();
        assert!((d - want).length() < 1e-6, "{d} vs {want}");
        // On the diagonal all three lookups are the same point: the bend is along (1, 1, 1).
        let diag = nm.perturb(Vec3::ZERO, Vec3::splat(0.37));
        assert!((diag.abs() - Vec3::splat(3f32.sqrt().recip())).length() < 1e-6);
        // The lattice is a zero of every lookup: no bend there.
        assert_eq!(nm.perturb(Vec3::Y, Vec3::new(1.0, -2.0, 3.5)), Vec3::Y);
    }

    #[test]
    fn components_are_decorrelated() {
        // Correlation between the x and y noise components over many points stays small.
        let nm = NormalMap {
            scale: 1.0,
            amount: 1.0,
        };
        let (mut sxy, mut sxx, mut syy) = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..4000 {
            let p = Vec3::new(
                i as f32 * 0.37,
                (i % 61) as f32 * 0.91,
                (i % 17) as f32 * 1.3,
            );
            let d = nm.perturb(Vec3::ZERO, p);
            sxy += (d.x * d.y) as f64;
            sxx += (d.x * d.x) as f64;
            syy += (d.y * d.y) as f64;
        }
        let r = sxy / (sxx * syy).sqrt();
        assert!(r.abs() < 0.1, "correlation {r}");
    }
}
