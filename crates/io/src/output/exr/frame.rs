//! A frame of a sequence in the EXR header: its place in time.
//!
//! | attribute         | type     | content                                                  |
//! |-------------------|----------|----------------------------------------------------------|
//! | `lumis/frame`     | int      | the frame number, from 0                                 |
//! | `framesPerSecond` | rational | the animation's rate, e.g. 24/1 or 24000/1001 (standard) |
//! | `timeCode`        | timecode | SMPTE `hh:mm:ss:ff` of the frame, non-drop, from 00:00:00:00 (standard), at whole rates up to 30 fps |
//!
//! SMPTE 12M counts at most 30 frames in a second and has no exact non-drop form for
//! 24000/1001 or 30000/1001, so other rates get no `timeCode`; `lumis/frame` and
//! `framesPerSecond` give the time exactly at every rate.

use ::exr::meta::attribute::TimeCode;
use ::exr::meta::header::Header;
use ::exr::prelude::{AnyChannels, AttributeValue, FlatSamples, Image, Layer, Text};

use lumis_core::scene::{Frame, FrameRate};

/// Custom int attribute: the frame number of an animation's frame.
pub const ATTR_FRAME: &str = "lumis/frame";

/// Writes `frame`'s attributes (module docs) into the header of `image`; nothing for a still.
pub(super) fn stamp(image: &mut Image<Layer<AnyChannels<FlatSamples>>>, frame: Option<Frame>) {
    let Some(frame) = frame else {
        return;
    };
    image.attributes.time_code = time_code(frame);
    let layer = &mut image.layer_data.attributes;
    let rate = frame.rate();
    // The rate's parts are at most 1001000 (FrameRate::new), within i32.
    let numerator = i32::try_from(rate.numerator()).unwrap_or(i32::MAX);
    layer.frames_per_second = Some((numerator, rate.denominator()));
    // Frame numbers are below MAX_FRAMES (1e6), within i32.
    let number = i32::try_from(frame.number()).unwrap_or(i32::MAX);
    layer
        .other
        .insert(Text::from(ATTR_FRAME), AttributeValue::I32(number));
}

/// The SMPTE time code of `frame` counted from 00:00:00:00 at a whole rate of at most 30 fps
/// (non-drop); `None` at other rates and past 23:59:59.
fn time_code(frame: Frame) -> Option<TimeCode> {
    let fps = frame.rate().whole().filter(|&f| f <= 30)?;
    let seconds = frame.number() / fps;
    let hours = u8::try_from(seconds / 3600).ok().filter(|&h| h <= 23)?;
    Some(TimeCode {
        hours,
        // Each below 60 or below fps <= 30: they fit a u8.
        minutes: (seconds / 60 % 60) as u8,
        seconds: (seconds % 60) as u8,
        frame: (frame.number() % fps) as u8,
        ..TimeCode::default()
    })
}

/// The frame `header` records, `None` for a still. The header has no frame count, so the frame
/// read back is the last of its animation (`count = number + 1`); the writer uses only the
/// number and the rate.
pub(super) fn read(header: &Header) -> Result<Option<Frame>, String> {
    let attributes = &header.own_attributes;
    let number = attributes.other.get(&Text::from(ATTR_FRAME));
    let (number, rate) = match (number, attributes.frames_per_second) {
        (None, None) => return Ok(None),
        (Some(AttributeValue::I32(n)), Some((num, den))) => (*n, (num, den)),
        _ => {
            return Err(format!(
                "{ATTR_FRAME} and framesPerSecond: expected both (an int and a rational) or \
                 neither"
            ));
        }
    };
    let number = u32::try_from(number).map_err(|_| format!("{ATTR_FRAME} = {number}"))?;
    let numerator = u32::try_from(rate.0).map_err(|_| format!("framesPerSecond {rate:?}"))?;
    let rate = FrameRate::new(numerator, rate.1).map_err(|e| format!("framesPerSecond: {e}"))?;
    let frame = Frame::new(number, number.saturating_add(1), rate)
        .map_err(|e| format!("{ATTR_FRAME}: {e}"))?;
    Ok(Some(frame))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(number: u32, rate: FrameRate) -> Frame {
        Frame::new(number, 1_000_000, rate).unwrap()
    }

    #[test]
    fn time_codes_count_whole_rates_up_to_30_fps() {
        let tc = |n, r| time_code(at(n, r)).map(|t| (t.hours, t.minutes, t.seconds, t.frame));
        let film = FrameRate::FILM;
        assert_eq!(tc(0, film), Some((0, 0, 0, 0)));
        assert_eq!(tc(23, film), Some((0, 0, 0, 23)));
        assert_eq!(tc(24, film), Some((0, 0, 1, 0)));
        assert_eq!(tc(24 * 3661 + 5, film), Some((1, 1, 1, 5)));
        assert_eq!(
            tc(999_999, FrameRate::new(30, 1).unwrap()),
            Some((9, 15, 33, 9))
        );
        assert_eq!(tc(5, FrameRate::new(24000, 1001).unwrap()), None);
        assert_eq!(tc(5, FrameRate::new(60, 1).unwrap()), None);
        // 24 hours at 1 fps do not fit the clock.
        assert_eq!(tc(86_400, FrameRate::new(1, 1).unwrap()), None);
        assert_eq!(
            tc(86_399, FrameRate::new(1, 1).unwrap()),
            Some((23, 59, 59, 0))
        );
        // Packing validates every field: what time_code makes, the writer accepts.
        for (n, rate) in [(999_999, 30), (86_399, 1), (24 * 3600 + 23, 24)] {
            let t = time_code(at(n, FrameRate::new(rate, 1).unwrap())).unwrap();
            assert!(t.pack_time_as_tv60_u32().is_ok(), "{t:?}");
        }
    }
}
