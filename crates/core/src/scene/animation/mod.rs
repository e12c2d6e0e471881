//! Frame sequences: which frame of an animation a scene is, at what rate, and the keyframe
//! [`Track`]s that loaders sample to pose the scene at that frame.
//!
//! A [`Scene`](super::Scene) is always a still: a loader evaluates the animation at the frame
//! asked for and builds the scene as it stands then, so nothing below the loaders knows about
//! time. The scene keeps the [`Frame`] it is, for the EXR header and the output file name.
//!
//! ```toml
//! [animation]
//! frames = 24          # frames 0..=23
//! fps = 24             # or [24000, 1001]
//!
//! [[animation.camera]]
//! frame = 0
//! position = [0.0, 1.0, 6.0]
//!
//! [[animation.camera]]
//! frame = 23
//! position = [6.0, 1.0, 0.0]
//! ```

mod track;

pub use track::{Interpolation, Key, Track, TrackError};

/// Most frames an animation may have (frames are numbered from 0): 11.5 hours at 24 fps, and
/// every frame number exact in `f32` (interpolation weights) and in an EXR int attribute.
pub const MAX_FRAMES: u32 = 1_000_000;
/// Highest frame rate, and the largest numerator or denominator of one.
pub const MAX_FPS: u32 = 1000;

/// Frames per second as the rational `numerator / denominator` (OpenEXR's `framesPerSecond`):
/// 24 is `24/1`, NTSC film rate `24000/1001`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameRate {
    numerator: u32,
    denominator: u32,
}

impl FrameRate {
    /// Film's 24 frames per second, the default.
    pub const FILM: Self = Self {
        numerator: 24,
        denominator: 1,
    };

    /// `numerator / denominator` frames per second; both in `1..=`[`MAX_FPS`]`*1001`, the rate
    /// in `[1 / MAX_FPS, MAX_FPS]`.
    pub fn new(numerator: u32, denominator: u32) -> Result<Self, String> {
        let most = MAX_FPS * 1001;
        if numerator == 0 || denominator == 0 || numerator > most || denominator > most {
            return Err(format!(
                "fps [{numerator}, {denominator}]: numerator and denominator must be in 1..={most}"
            ));
        }
        let rate = f64::from(numerator) / f64::from(denominator);
        if !(1.0 / f64::from(MAX_FPS)..=f64::from(MAX_FPS)).contains(&rate) {
            return Err(format!(
                "fps {numerator}/{denominator} = {rate}: expected a rate in [1/{MAX_FPS}, {MAX_FPS}]"
            ));
        }
        Ok(Self {
            numerator,
            denominator,
        })
    }

    /// The numerator.
    pub fn numerator(self) -> u32 {
        self.numerator
    }

    /// The denominator (1 for a whole number of frames per second).
    pub fn denominator(self) -> u32 {
        self.denominator
    }

    /// The whole number of frames per second, when the rate is one.
    pub fn whole(self) -> Option<u32> {
        self.numerator
            .is_multiple_of(self.denominator)
            .then(|| self.numerator / self.denominator)
    }
}

impl Default for FrameRate {
    fn default() -> Self {
        Self::FILM
    }
}

/// Which frame of how many a scene shows, and the animation's rate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Frame {
    number: u32,
    count: u32,
    rate: FrameRate,
}

impl Frame {
    /// Frame `number` of an animation of `count` frames (`number < count <= MAX_FRAMES`).
    pub fn new(number: u32, count: u32, rate: FrameRate) -> Result<Self, String> {
        if count == 0 || count > MAX_FRAMES {
            return Err(format!("frames = {count}: expected 1..={MAX_FRAMES}"));
        }
        if number >= count {
            return Err(format!(
                "frame {number} is out of range: frames = {count} numbers them 0..={}",
                count - 1
            ));
        }
        Ok(Self {
            number,
            count,
            rate,
        })
    }

    /// The frame number, from 0.
    pub fn number(self) -> u32 {
        self.number
    }

    /// How many frames the animation has.
    pub fn count(self) -> u32 {
        self.count
    }

    /// The animation's frame rate.
    pub fn rate(self) -> FrameRate {
        self.rate
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rates_are_checked_and_whole_rates_known() {
        assert_eq!(FrameRate::default().whole(), Some(24));
        assert_eq!(FrameRate::new(24000, 1001).unwrap().whole(), None);
        assert_eq!(FrameRate::new(50, 2).unwrap().whole(), Some(25));
        assert!(FrameRate::new(0, 1).is_err());
        assert!(FrameRate::new(24, 0).is_err());
        assert!(
            FrameRate::new(1001, 1)
                .unwrap_err()
                .contains("[1/1000, 1000]")
        );
        assert!(FrameRate::new(1, 1001).is_err());
    }

    #[test]
    fn frames_lie_in_the_animation() {
        let f = Frame::new(23, 24, FrameRate::FILM).unwrap();
        assert_eq!((f.number(), f.count()), (23, 24));
        let e = Frame::new(24, 24, FrameRate::FILM).unwrap_err();
        assert_eq!(
            e,
            "frame 24 is out of range: frames = 24 numbers them 0..=23"
        );
        assert!(Frame::new(0, 0, FrameRate::FILM).is_err());
        assert!(Frame::new(0, MAX_FRAMES + 1, FrameRate::FILM).is_err());
    }
}
