//! Only the effects a scene calls for: every skip the renderer takes is proven to change no
//! bit of the image (against `--effects all`, which traces everything), and every effect a
//! scene lacks costs zero rays.

use crate::common;
mod identical;
mod levels;
mod stats_json;

use lumis_core::accel::{AccelKind, BuildOptions};
use lumis_core::effects::EffectMode;
use lumis_core::film::Film;
use lumis_core::render::{RenderOptions, Rendered, render};
use lumis_core::scene::{Scene, World};

/// Renders `scene` under `mode` with every AOV layer.
pub fn render_mode(scene: &Scene, mode: EffectMode) -> Rendered {
    let world = World::build(scene.clone(), AccelKind::Sah, &BuildOptions::default());
    let opts = RenderOptions {
        effects: mode,
        ..RenderOptions::default()
    };
    render(&world, &opts).expect("render")
}

/// Panics unless two films hold the same bits in RGBA and every AOV layer.
pub fn assert_same_bits(what: &str, a: &Film, b: &Film) {
    let rgba = |f: &Film| -> Vec<u32> {
        f.rgba()
            .iter()
            .flat_map(|p| p.to_array().map(f32::to_bits))
            .collect()
    };
    let aov = |f: &Film| -> Vec<(u32, [u32; 3], i32, i32)> {
        f.aov()
            .iter()
            .map(|a| {
                (
                    a.depth.to_bits(),
                    a.normal.to_array().map(f32::to_bits),
                    a.prim_id,
                    a.object_id,
                )
            })
            .collect()
    };
    let (ra, rb) = (rgba(a), rgba(b));
    if let Some(i) = (0..ra.len()).find(|&i| ra[i] != rb[i]) {
        let px = i / 4;
        panic!(
            "{what}: RGBA differs at pixel ({}, {}): {:?} vs {:?}",
            px as u32 % a.width(),
            px as u32 / a.width(),
            a.rgba()[px],
            b.rgba()[px]
        );
    }
    assert!(aov(a) == aov(b), "{what}: AOV layers differ");
}

/// Renders `scene` at cutoff 0 under both modes, checks the bits agree, returns both.
pub fn auto_and_all(what: &str, scene: &mut Scene) -> (Rendered, Rendered) {
    scene.settings_mut().cutoff = 0.0;
    let auto = render_mode(scene, EffectMode::Auto);
    let all = render_mode(scene, EffectMode::All);
    assert_same_bits(what, &auto.film, &all.film);
    // The reference really traced more: it is not the same code path twice.
    assert!(
        all.counts.total() >= auto.counts.total(),
        "{what}: --effects all traced fewer rays ({} < {})",
        all.counts.total(),
        auto.counts.total()
    );
    (auto, all)
}
