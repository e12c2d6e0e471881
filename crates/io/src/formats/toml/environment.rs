//! `[environment]`: the HDR latitude-longitude image around the scene, in every format
//! (TOML scenes write the table; `-D environment.KEY=VALUE` and `--env` set it for any file).
//!
//! ```toml
//! [environment]
//! file = "sky.hdr"     # Radiance .hdr or OpenEXR, relative to the scene file
//! rotation = 90.0      # degrees about +Y, as Mitsuba 3's envmap to_world rotation
//! intensity = 1.0      # scale of every texel
//! sun = false          # take the brightest compact region out as a directional light
//! ```
//!
//! With an environment, escaping rays see it (camera rays unless `--transparent`) and the
//! ambient term is its diffuse irradiance: the constant `[render] ambient` and `background`
//! are not used.

use std::path::Path;
use std::sync::Arc;

use super::schema::EnvironmentDoc;
use crate::formats::environment::decode_environment_image;
use crate::formats::{Resolver, SceneError};
use lumis_core::environment::{Environment, LatLong, Placement};
use lumis_core::math::Vec3;
use lumis_core::scene::Scene;

/// Sets the environment `doc` describes on `scene`; `origin` is the scene file (relative
/// paths start in its folder and errors name it).
pub(crate) fn apply(
    scene: &mut Scene,
    doc: &EnvironmentDoc,
    origin: &Path,
    resolver: Resolver<'_>,
) -> Result<(), SceneError> {
    let invalid = |m: String| SceneError::invalid(origin, "environment", m);
    let Some(file) = &doc.file else {
        return Err(invalid(
            "no file: expected file = \"sky.hdr\" (a Radiance .hdr or OpenEXR \
             latitude-longitude image)"
                .into(),
        ));
    };
    let path = origin
        .parent()
        .unwrap_or(Path::new(""))
        .join(Path::new(file));
    let bytes = resolver(&path).map_err(|source| SceneError::Read {
        path: path.clone(),
        source,
    })?;
    let image = decode_environment_image(&bytes, &path)?;
    let texels = image.texels.iter().map(|t| Vec3::from_array(*t)).collect();
    let map = LatLong::new(image.width, image.height, texels)
        .ok_or_else(|| invalid(format!("{}: an empty image", path.display())))?;
    let placement = Placement {
        rotation_degrees: doc.rotation.unwrap_or(0.0),
        intensity: doc.intensity.unwrap_or(1.0),
    };
    let env = Environment::new(
        map,
        placement,
        doc.sun.unwrap_or(false),
        path.display().to_string(),
    )
    .map_err(invalid)?;
    if image.clamped > 0 {
        scene.warn(format!(
            "{}: {} texel(s) were not finite, negative or above 1e6 and were clamped \
             (NaN and negative to 0, the rest to 1e6)",
            path.display(),
            image.clamped
        ));
    }
    scene.set_environment(Some(Arc::new(env)));
    Ok(())
}
