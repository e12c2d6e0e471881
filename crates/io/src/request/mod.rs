//! What a render is asked for on top of its scene: the settings the caller sets over the
//! scene's, the exposure, the extra EXR layers. Decided here once, for `lumis render` and the
//! Python package's `Scene.render` alike, so that the same request gives the same image from
//! either.
//!
//! Each choice is spelled by its type's `name` and parsed by its `FromStr`: [`Aov`] here,
//! [`ChannelLayout`](crate::output::ChannelLayout), and lumis-core's `Tonemap`,
//! `DisplayTransform`, `Precision`, `AccelKind` and `UpAxis`. The frontends only wrap a bad
//! name in their own words (a flag, a keyword argument).

mod aov;
mod exposure;
mod settings_record;

pub use aov::{Aov, aov_layers, pass_request};
pub use exposure::{SceneOrigin, check_exposure, exposure_to_apply};
pub use settings_record::settings_record;

use lumis_core::film::DisplayTransform;
use lumis_core::geometry::Precision;
use lumis_core::scene::Settings;

/// The render settings a caller sets over the scene's (`--width`, `width=`, ...); `None`
/// keeps the scene's value. The result still has to pass `Settings::validate`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SettingsFlags {
    pub width: Option<u32>,
    pub height: Option<u32>,
    /// Samples per pixel along each axis.
    pub spp: Option<u32>,
    pub max_depth: Option<u32>,
    pub precision: Option<Precision>,
    /// The PNG's display transform.
    pub display: Option<DisplayTransform>,
}

impl SettingsFlags {
    /// Sets the given values over `st`.
    pub fn apply(&self, st: &mut Settings) {
        st.width = self.width.unwrap_or(st.width);
        st.height = self.height.unwrap_or(st.height);
        st.spp = self.spp.unwrap_or(st.spp);
        st.max_depth = self.max_depth.unwrap_or(st.max_depth);
        st.precision = self.precision.unwrap_or(st.precision);
        st.display = self.display.unwrap_or(st.display);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_set_what_is_given_and_keep_the_rest() {
        let scene = Settings {
            width: 7,
            height: 5,
            spp: 3,
            max_depth: 4,
            precision: Precision::Fast,
            display: DisplayTransform::Clamp,
            ..Settings::default()
        };
        let mut st = scene.clone();
        SettingsFlags::default().apply(&mut st);
        assert_eq!(st, scene);
        let flags = SettingsFlags {
            width: Some(11),
            spp: Some(1),
            precision: Some(Precision::Double),
            display: Some(DisplayTransform::Srgb),
            ..SettingsFlags::default()
        };
        flags.apply(&mut st);
        let (w, h, spp, depth) = (st.width, st.height, st.spp, st.max_depth);
        assert_eq!((w, h, spp, depth), (11, 5, 1, 4));
        assert_eq!(
            (st.precision, st.display),
            (Precision::Double, DisplayTransform::Srgb)
        );
    }
}
