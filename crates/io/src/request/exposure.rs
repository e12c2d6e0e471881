//! The exposure rule: the exposure given, else the scene's `exposure`, else, for a bare model
//! (a glTF or OBJ file, or a mesh from arrays, none of which says how bright it should look),
//! automatic from the rendered image.

use std::path::Path;

use lumis_core::scene::limits::MAX_EXPOSURE;

use crate::formats::is_model_file;

/// Where a render's scene came from, as far as the exposure rule cares.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneOrigin<'a> {
    /// A scene file.
    File(&'a Path),
    /// lumis's built-in default scene.
    BuiltIn,
    /// Meshes and spheres from arrays (the Python package's `SceneBuilder`): a bare model.
    Arrays,
}

impl SceneOrigin<'_> {
    /// Whether the scene is a bare model, exposed automatically unless told otherwise.
    pub fn is_bare_model(self) -> bool {
        match self {
            SceneOrigin::File(path) => is_model_file(path),
            SceneOrigin::BuiltIn => false,
            SceneOrigin::Arrays => true,
        }
    }
}

/// `ev` if it is an exposure a render can apply, else what was expected (the caller names
/// the flag or argument).
pub fn check_exposure(ev: f32) -> Result<f32, String> {
    if ev.is_nan() || ev.abs() > MAX_EXPOSURE {
        return Err("expected a finite number of stops within +-64".to_owned());
    }
    Ok(ev)
}

/// The exposure to apply, in stops, decided before the render: `given`, else the scene's
/// `scene_exposure`, except that a bare model gets `None`: automatic, from the film.
pub fn exposure_to_apply(
    given: Option<f32>,
    origin: SceneOrigin<'_>,
    scene_exposure: f32,
) -> Option<f32> {
    match given {
        Some(ev) => Some(ev),
        None if origin.is_bare_model() => None,
        None => Some(scene_exposure),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn given_wins_then_the_scene_then_automatic_for_bare_models() {
        let toml = SceneOrigin::File(Path::new("scenes/default.toml"));
        let scn = SceneOrigin::File(Path::new("a.scn"));
        let obj = SceneOrigin::File(Path::new("dir.x/Model.OBJ"));
        let glb = SceneOrigin::File(Path::new("m.glb"));
        let gltf = SceneOrigin::File(Path::new("m.gltf"));
        for origin in [
            toml,
            scn,
            obj,
            glb,
            gltf,
            SceneOrigin::BuiltIn,
            SceneOrigin::Arrays,
        ] {
            assert_eq!(exposure_to_apply(Some(-1.5), origin, 2.0), Some(-1.5));
        }
        for origin in [toml, scn, SceneOrigin::BuiltIn] {
            assert_eq!(
                exposure_to_apply(None, origin, 2.0),
                Some(2.0),
                "{origin:?}"
            );
        }
        for origin in [obj, glb, gltf, SceneOrigin::Arrays] {
            assert_eq!(exposure_to_apply(None, origin, 2.0), None, "{origin:?}");
        }
        // A directory named like a model is not one; a file without an extension neither.
        assert!(!SceneOrigin::File(Path::new("m.obj/scene.toml")).is_bare_model());
        assert!(!SceneOrigin::File(Path::new("obj")).is_bare_model());
    }

    #[test]
    fn exposures_beyond_64_stops_or_nan_are_refused() {
        for ev in [0.0, -64.0, 64.0, 0.5] {
            assert_eq!(check_exposure(ev), Ok(ev));
        }
        for ev in [f32::NAN, 64.001, -65.0, f32::INFINITY, f32::NEG_INFINITY] {
            assert_eq!(
                check_exposure(ev).unwrap_err(),
                "expected a finite number of stops within +-64"
            );
        }
    }
}
