//! The brute-force reference: every primitive, in index order.

use super::{Closest, Hit, TraversalStats};
use crate::geometry::PrimHit;
use crate::math::{Aabb, Ray};

/// Tests all `count` primitives for every ray.
#[derive(Clone, Debug)]
pub struct Brute {
    count: u32,
}

impl Brute {
    /// A reference over as many primitives as there are bounds.
    pub fn new(bounds: &[Aabb]) -> Self {
        Self {
            count: bounds.len() as u32,
        }
    }

    /// See [`super::Accel::intersect`].
    pub fn intersect<F>(&self, ray: &Ray, stats: &mut TraversalStats, mut test: F) -> Option<Hit>
    where
        F: FnMut(u32, &Ray) -> Option<PrimHit>,
    {
        let mut closest = Closest::new(ray);
        for prim in 0..self.count {
            stats.prim_tests += 1;
            if let Some(h) = test(prim, &closest.ray) {
                closest.offer(prim, h);
            }
        }
        closest.best
    }

    /// See [`super::Accel::occluded`].
    pub fn occluded<F>(&self, ray: &Ray, stats: &mut TraversalStats, mut test: F) -> bool
    where
        F: FnMut(u32, &Ray) -> bool,
    {
        (0..self.count).any(|prim| {
            stats.prim_tests += 1;
            test(prim, ray)
        })
    }
}
