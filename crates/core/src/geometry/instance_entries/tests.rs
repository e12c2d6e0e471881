//! Lanes of the eight-wide entry against the one-ray entry.

use glam::{DAffine3, DQuat, DVec3};

use super::*;
use crate::geometry::{Mesh, Placement, Precision, PrimHit, PrototypeQueries};
use crate::math::{Aabb, Vec3};

/// A prototype for entering only: its shapes and box (the geometry may not reach the
/// hierarchies above it, `tests/it/module_flow.rs`); nothing is traced inside it.
#[derive(Debug)]
struct Shapes(Geometry);

impl PrototypeQueries for Shapes {
    fn geometry(&self) -> &Geometry {
        &self.0
    }
    fn bounds(&self) -> Aabb {
        self.0.bounds()
    }
    fn nearest(&self, _: &Ray, _: Precision) -> Option<PrimHit> {
        unreachable!("entering traces nothing")
    }
    fn blocks(&self, _: &Ray, _: Precision) -> bool {
        unreachable!("entering traces nothing")
    }
    fn all_hits(&self, _: &Ray, _: Precision) -> Vec<(PrimHit, bool)> {
        unreachable!("entering traces nothing")
    }
    fn bytes(&self) -> usize {
        0
    }
    fn hierarchy(&self) -> &dyn std::any::Any {
        &()
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// A seeded stream of awkward floats: ordinary values, zeros of both signs, subnormals,
/// huge and infinite ones, NaN.
struct Floats(u64);

impl Floats {
    fn bits(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }

    fn unit(&mut self) -> f32 {
        (self.bits() % 1_000_000) as f32 / 500_000.0 - 1.0
    }

    fn awkward(&mut self, scale: f32) -> f32 {
        match self.bits() % 16 {
            0 => 0.0,
            1 => -0.0,
            2 => f32::from_bits(self.bits() as u32 & 0x807f_ffff),
            3 => self.unit() * 1e30,
            4 => f32::INFINITY,
            5 => f32::NAN,
            _ => self.unit() * scale,
        }
    }
}

fn scene(to_world: DAffine3) -> Geometry {
    let mesh = Mesh::new(
        vec![
            Vec3::new(-1.0, -1.0, -1.0),
            Vec3::new(1.0, -1.0, 0.5),
            Vec3::new(0.0, 1.0, 1.0),
            Vec3::new(0.5, 0.5, -1.0),
        ],
        None,
        None,
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .unwrap();
    let mut shapes = Geometry::new();
    shapes.add_mesh(mesh);
    let mut g = Geometry::new();
    let proto = g.add_prototype(std::sync::Arc::new(Shapes(shapes)));
    g.add_instance(proto, Placement::new(to_world).unwrap());
    g
}

#[test]
fn every_lane_enters_as_the_one_ray_entry_does() {
    let placements = [
        DAffine3::IDENTITY,
        DAffine3::from_scale_rotation_translation(
            DVec3::new(2.0, -0.5, 3.0),
            DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 2.0),
            DVec3::new(5.0, -2.0, 1.0),
        ),
        DAffine3::from_scale(DVec3::splat(1e-6)),
        DAffine3::from_scale_rotation_translation(
            DVec3::new(1e6, 1e6, -1e6),
            DQuat::from_rotation_y(0.7),
            DVec3::new(1e6, 0.0, -3e6),
        ),
    ];
    let mut f = Floats(7);
    let (mut covered, mut objects, mut held_lanes) = (0, 0, 0);
    // The prototype's frame: the walk takes the object-space rays it holds.
    let frame = crate::geometry::frame::RayFrame::new(Aabb {
        min: Vec3::splat(-1.0),
        max: Vec3::ONE,
    });
    for to_world in placements {
        let g = scene(to_world);
        let b = g.instances()[0].bounds;
        let (centre, size) = (b.center(), (b.max - b.min).max_element());
        for _ in 0..4000 {
            let n = 1 + (f.bits() % ENTRY_BLOCK as u64) as usize;
            let rays: Vec<Ray> = (0..n)
                .map(|_| {
                    // Origins around the box (some far), directions of every kind.
                    let reach = if f.bits().is_multiple_of(8) { 1e4 } else { 3.0 } * size;
                    let origin = centre + Vec3::new(f.unit(), f.unit(), f.unit()) * reach;
                    let towards = centre - origin + Vec3::new(f.unit(), f.unit(), f.unit()) * size;
                    let dir = if f.bits().is_multiple_of(3) {
                        Vec3::new(f.awkward(1.0), f.awkward(1.0), f.awkward(1.0))
                    } else {
                        towards * f.unit().abs()
                    };
                    let t_min = [0.0, -0.0, f.unit(), f32::NEG_INFINITY][f.bits() as usize % 4];
                    let t_max = [f32::INFINITY, f.unit().abs() * 2.0, 0.5][f.bits() as usize % 3];
                    Ray {
                        origin,
                        dir,
                        t_min,
                        t_max,
                    }
                })
                .collect();
            let mut out = Entries::new();
            g.enter_instance(0, &rays, &frame, &mut out);
            for (k, ray) in rays.iter().enumerate() {
                let one = Entry::of(g.instance_ray_as_given(0, ray));
                // `==` on the floats: +0 and -0 are equal (see the module docs).
                assert_eq!(out.entry(k), one, "lane {k} of {n}: {ray:?}");
                let held = matches!(one, Entry::Object(o) if frame.holds(o.origin));
                assert_eq!(out.held & (1 << k) != 0, held, "lane {k} of {n}: {ray:?}");
                held_lanes += held as u32;
                objects += matches!(one, Entry::Object(_)) as u32;
            }
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: AVX2 is present.
                let lanes = unsafe { avx2::enter(&g.instances()[0], &rays, &frame, &mut out) };
                covered += lanes.count_ones();
            }
        }
    }
    // The eight-wide path and the box both had work to do.
    assert!(objects > 5000, "{objects} object rays");
    // Some object-space rays start far from the prototype, most near it.
    assert!(
        held_lanes > objects / 2 && held_lanes < objects,
        "{held_lanes} of {objects} held"
    );
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        assert!(covered > 20000, "{covered} lanes covered");
    }
}
