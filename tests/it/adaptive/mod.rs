//! Adaptive supersampling (`--adaptive T`): at T = 0 the full render bit for bit; decisions
//! independent of threads, crops and farm tiles; flat regions keep the base pass, edges take
//! every sample; the samples, alpha, passes and Cryptomatte coverage agree with the count.

mod cli;
mod identical;
mod skipping;

use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::camera::Lens;
use lumis_core::film::Film;
use lumis_core::render::{RenderOptions, Rendered, render};
use lumis_core::scene::World;

/// The built-in default scene (depth of field, glass, mirror, two lights) at `w x h` with
/// `spp x spp` samples; `pinhole` takes its lens away.
fn default_world(w: u32, h: u32, spp: u32, pinhole: bool) -> World {
    let mut scene = lumis_io::formats::default_scene().unwrap();
    let st = scene.settings_mut();
    (st.width, st.height, st.spp) = (w, h, spp);
    if pinhole {
        let camera = scene.camera().clone().with_lens(Lens::Pinhole);
        scene.set_camera(camera);
    }
    World::build(scene, AccelKind::Sah, &BuildOptions::default())
}

/// `world` rendered with adaptive threshold `t` (`None`: off) and `opts`.
fn render_at(world: &mut World, t: Option<f32>, opts: &RenderOptions) -> Rendered {
    world.settings_mut().adaptive = t;
    render(world, opts).unwrap()
}

/// Every value of the two films is the same, the colour compared bit for bit.
fn assert_same_film(a: &Film, b: &Film, what: &str) {
    let bits = |f: &Film| -> Vec<[u32; 4]> {
        f.rgba()
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect()
    };
    assert!(bits(a) == bits(b), "{what}: the colour differs");
    for (pa, pb) in a.passes().iter().zip(b.passes()) {
        let bits = |p: &lumis_core::film::PassLayer| -> Vec<[u32; 3]> {
            p.values()
                .iter()
                .map(|v| v.to_array().map(f32::to_bits))
                .collect()
        };
        assert!(bits(pa) == bits(pb), "{what}: pass {} differs", pa.name());
    }
    assert!(a == b, "{what}: the films differ");
}
