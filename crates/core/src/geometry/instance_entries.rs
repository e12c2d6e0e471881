//! Several world rays entering one instance at once: [`Geometry::instance_ray_as_given`] for up
//! to [`ENTRY_BLOCK`] rays, eight lanes wide. A batch of rays through a scene of one instance
//! (`crate::accel::one_instance`) enters the instance with every ray; one at a time, the frame
//! test, the box clip and the `f64` transform cost about as much as a quarter of the walk.
//!
//! Each lane takes the scalar steps in the same order with the same IEEE operations (no fused
//! multiply-adds, the slab test's `min`/`max` operand order, the transform's sums left to
//! right), so its object-space ray is the scalar one's bit for bit. Lanes the common case does
//! not cover (an origin outside the instance's near region, a direction whose slab test is not
//! the plain `f32` one) take the scalar path itself. A `-0` where the scalar path has `+0` can
//! appear in an interval end (the maxima and minima of equal zeros): interval ends only meet
//! comparisons, where the two are equal. `tests` check lanes against the scalar path.

use super::Geometry;
use super::frame::RayFrame;
use crate::math::Ray;

/// Rays entered at once.
pub(crate) const ENTRY_BLOCK: usize = 8;

/// What entering an instance gives a world ray ([`Geometry::instance_ray_as_given`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Entry {
    /// The object-space ray to trace as given.
    Object(Ray),
    /// Nothing in the instance's box can be hit.
    Misses,
    /// The instance frames the ray first (its origin is far away): its nested query answers.
    Framed,
}

impl Entry {
    fn of(entered: Result<Option<(u32, Ray)>, ()>) -> Self {
        match entered {
            Ok(Some((_, object))) => Entry::Object(object),
            Ok(None) => Entry::Misses,
            Err(()) => Entry::Framed,
        }
    }
}

/// The entries of a block of rays: lane `k`'s object-space ray in `objects[k]` when bit `k` of
/// `object` is set; otherwise `Framed` when bit `k` of `framed` is, else `Misses`. Bit `k` of
/// `held`: lane `k`'s object-space ray starts in the near region of the frame the entry was
/// given (the prototype's: its walk takes that ray as given).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Entries {
    pub(crate) objects: [Ray; ENTRY_BLOCK],
    pub(crate) object: u32,
    pub(crate) framed: u32,
    pub(crate) held: u32,
}

impl Entries {
    /// No entries yet.
    pub(crate) fn new() -> Self {
        Self {
            objects: [Ray::new(crate::math::Vec3::ZERO, crate::math::Vec3::X); ENTRY_BLOCK],
            object: 0,
            framed: 0,
            held: 0,
        }
    }

    /// The entry of lane `k`.
    #[inline(always)]
    pub(crate) fn entry(&self, k: usize) -> Entry {
        if self.object & (1 << k) != 0 {
            Entry::Object(self.objects[k])
        } else if self.framed & (1 << k) != 0 {
            Entry::Framed
        } else {
            Entry::Misses
        }
    }

    /// Sets lane `k` to `entry`, held as `frame` holds it.
    fn set(&mut self, k: usize, entry: Entry, frame: &RayFrame) {
        let bit = 1 << k;
        self.object &= !bit;
        self.framed &= !bit;
        self.held &= !bit;
        match entry {
            Entry::Object(ray) => {
                self.objects[k] = ray;
                self.object |= bit;
                self.held |= (frame.holds(ray.origin) as u32) << k;
            }
            Entry::Misses => {}
            Entry::Framed => self.framed |= bit,
        }
    }
}

impl Geometry {
    /// The entry of each of `rays` (at most [`ENTRY_BLOCK`]) into instance `instance`, in `out`,
    /// with the object-space rays `frame` holds marked.
    pub(crate) fn enter_instance(
        &self,
        instance: u32,
        rays: &[Ray],
        frame: &RayFrame,
        out: &mut Entries,
    ) {
        debug_assert!(rays.len() <= ENTRY_BLOCK);
        out.object = 0;
        out.framed = 0;
        out.held = 0;
        let mut rest: u32 = (1 << rays.len()) - 1;
        #[cfg(target_arch = "x86_64")]
        if !rays.is_empty() && std::arch::is_x86_feature_detected!("avx2") {
            let inst = &self.instances[instance as usize];
            // SAFETY: AVX2 is present.
            rest &= !unsafe { avx2::enter(inst, rays, frame, out) };
        }
        // The lanes the eight-wide entry does not cover (rare), or all without AVX2: one at
        // a time.
        while rest != 0 {
            let k = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            let entry = Entry::of(self.instance_ray_as_given(instance, &rays[k]));
            out.set(k, entry, frame);
        }
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2;

#[cfg(test)]
mod tests;
