//! Loading and rendering the project's model files for pixel tests, with one choice of seed
//! and threads, so that two tests rendering the same file see the same pixels.

use std::path::Path;

use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::film::Film;
use lumis_core::render::{RenderOptions, render};
use lumis_core::scene::{Scene, World};
use lumis_io::formats;

/// The scene in `path`; a load error fails the test with its whole chain.
pub fn load(path: &Path) -> Scene {
    formats::load(path).unwrap_or_else(|e| panic!("{}: {e:#}", path.display()))
}

/// `scene` at `width` x `height`, one sample a pixel, through `kind` built with `build`; seed 1
/// and two threads (the pixels do not depend on the thread count).
pub fn film(
    mut scene: Scene,
    (width, height): (u32, u32),
    kind: AccelKind,
    build: &BuildOptions,
) -> Film {
    let st = scene.settings_mut();
    (st.width, st.height, st.spp) = (width, height, 1);
    let world = World::build(scene, kind, build);
    let opts = RenderOptions {
        seed: 1,
        threads: Some(2),
        ..RenderOptions::default()
    };
    render(&world, &opts).unwrap().film
}
