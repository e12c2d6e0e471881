//! Keyframe tracks: one animated value (a camera's `position`, its `fov`) as keys at whole
//! frames, sampled at any frame of the animation.
//!
//! Between two keys the value follows the earlier key's [`Interpolation`] (Blender's rule: a
//! keyframe's interpolation governs the segment after it); before the first key and after the
//! last the value holds. A key's value is returned bit for bit at its own frame, so a frame
//! that is a key renders exactly as a still scene with those values written by hand.

/// How a value moves from one key to the next.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Interpolation {
    /// A straight line between the two keys' values.
    #[default]
    Linear,
    /// The key's value holds until the next key's frame.
    Step,
}

/// A value of `N` components at frame `frame`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Key<const N: usize> {
    /// The whole frame the key sits on.
    pub frame: u32,
    /// The value there.
    pub value: [f32; N],
    /// How the value leaves this key for the next.
    pub interpolation: Interpolation,
}

/// Why keys do not make a track.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TrackError {
    /// Two keys sit on the same frame (indices into the keys as given).
    #[error("keys {first} and {second} are both at frame {frame}")]
    Duplicate {
        /// The frame.
        frame: u32,
        /// The earlier key as given.
        first: usize,
        /// The later key as given.
        second: usize,
    },
    /// A component is NaN or infinite (index of the key as given).
    #[error("key {key} has a non-finite value")]
    NonFinite {
        /// The key as given.
        key: usize,
    },
}

/// Keys of one value, sorted by frame, at least one, no two on the same frame, every value
/// finite.
#[derive(Clone, Debug, PartialEq)]
pub struct Track<const N: usize> {
    keys: Vec<Key<N>>,
}

impl<const N: usize> Track<N> {
    /// A track of `keys` in any order (they are sorted by frame); `None` when there are none.
    /// Two keys on one frame, or a non-finite value, are errors naming the keys by their
    /// position in `keys`.
    pub fn new(keys: Vec<Key<N>>) -> Result<Option<Self>, TrackError> {
        if let Some(key) = keys
            .iter()
            .position(|k| !k.value.iter().all(|v| v.is_finite()))
        {
            return Err(TrackError::NonFinite { key });
        }
        let mut order: Vec<usize> = (0..keys.len()).collect();
        // Stable, so of two keys on one frame the earlier in the file is named first.
        order.sort_by_key(|&i| keys[i].frame);
        if let Some(pair) = order
            .windows(2)
            .find(|w| keys[w[0]].frame == keys[w[1]].frame)
        {
            return Err(TrackError::Duplicate {
                frame: keys[pair[0]].frame,
                first: pair[0],
                second: pair[1],
            });
        }
        if keys.is_empty() {
            return Ok(None);
        }
        Ok(Some(Self {
            keys: order.into_iter().map(|i| keys[i]).collect(),
        }))
    }

    /// The keys, sorted by frame.
    pub fn keys(&self) -> &[Key<N>] {
        &self.keys
    }

    /// The value at `frame`: the key's own value on a key, the interpolation of the two keys
    /// around it between keys, the nearest key's value outside them.
    pub fn sample(&self, frame: u32) -> [f32; N] {
        // The first key after `frame`; the one before it governs the segment.
        let next = self.keys.partition_point(|k| k.frame <= frame);
        let (Some(a), Some(b)) = (
            next.checked_sub(1).map(|i| &self.keys[i]),
            self.keys.get(next),
        ) else {
            // Before the first key or at/after the last: hold.
            return self.keys[next.saturating_sub(1)].value;
        };
        match a.interpolation {
            Interpolation::Step => a.value,
            Interpolation::Linear => {
                // Frames are below 2^24, so both differences are exact in f32; t is in [0, 1).
                let t = (frame - a.frame) as f32 / (b.frame - a.frame) as f32;
                std::array::from_fn(|i| lerp(a.value[i], b.value[i], t))
            }
        }
    }
}

/// `a + (b - a) t`: exactly `a` at `t = 0` (the key's frame), and exact halfway between values
/// whose difference and half-difference are representable.
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(frame: u32, v: f32) -> Key<1> {
        Key {
            frame,
            value: [v],
            interpolation: Interpolation::Linear,
        }
    }

    fn track(keys: &[Key<1>]) -> Track<1> {
        Track::new(keys.to_vec()).unwrap().unwrap()
    }

    #[test]
    fn keys_are_exact_and_halfway_is_the_mean() {
        let t = track(&[key(0, 0.0), key(4, 2.0), key(8, -6.0)]);
        let at = |f| t.sample(f)[0];
        assert_eq!([at(0), at(4), at(8)], [0.0, 2.0, -6.0]);
        assert_eq!([at(1), at(2), at(3)], [0.5, 1.0, 1.5]);
        assert_eq!(at(6), -2.0);
        // A value that is not a short binary fraction still comes back bit for bit on its key.
        let t = track(&[key(0, 0.1), key(3, 0.7)]);
        assert_eq!(t.sample(0)[0].to_bits(), 0.1f32.to_bits());
        assert_eq!(t.sample(3)[0].to_bits(), 0.7f32.to_bits());
    }

    #[test]
    fn values_hold_before_the_first_and_after_the_last_key() {
        let t = track(&[key(5, 1.0), key(10, 3.0)]);
        assert_eq!([t.sample(0)[0], t.sample(4)[0]], [1.0, 1.0]);
        assert_eq!([t.sample(11)[0], t.sample(u32::MAX)[0]], [3.0, 3.0]);
        let single = track(&[key(7, 4.0)]);
        assert_eq!([single.sample(0)[0], single.sample(100)[0]], [4.0, 4.0]);
    }

    #[test]
    fn a_step_key_holds_until_the_next_key() {
        let mut keys = [key(0, 1.0), key(4, 5.0), key(8, 9.0)];
        keys[0].interpolation = Interpolation::Step;
        let t = track(&keys);
        let at: Vec<f32> = (0..=8).map(|f| t.sample(f)[0]).collect();
        assert_eq!(at, [1.0, 1.0, 1.0, 1.0, 5.0, 6.0, 7.0, 8.0, 9.0]);
    }

    #[test]
    fn keys_are_sorted_and_duplicates_and_non_finite_values_refused() {
        let t = track(&[key(8, 8.0), key(0, 0.0), key(4, 4.0)]);
        let frames: Vec<u32> = t.keys().iter().map(|k| k.frame).collect();
        assert_eq!(frames, [0, 4, 8]);
        assert_eq!(t.sample(2)[0], 2.0);
        assert_eq!(
            Track::new(vec![key(3, 0.0), key(1, 0.0), key(3, 1.0)]),
            Err(TrackError::Duplicate {
                frame: 3,
                first: 0,
                second: 2
            })
        );
        assert_eq!(
            Track::new(vec![key(0, 0.0), key(1, f32::NAN)]),
            Err(TrackError::NonFinite { key: 1 })
        );
        assert_eq!(Track::<1>::new(Vec::new()), Ok(None));
    }

    #[test]
    fn vectors_interpolate_per_component() {
        let keys = vec![
            Key {
                frame: 0,
                value: [0.0, 4.0, -1.0],
                interpolation: Interpolation::Linear,
            },
            Key {
                frame: 2,
                value: [2.0, 0.0, -1.0],
                interpolation: Interpolation::Linear,
            },
        ];
        let t = Track::new(keys).unwrap().unwrap();
        assert_eq!(t.sample(1), [1.0, 2.0, -1.0]);
    }
}
