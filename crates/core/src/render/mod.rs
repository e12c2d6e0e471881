//! Drives the integrator over the image: rayon over 16x16 tiles, stratified jittered samples,
//! progress reported to whoever listens ([`ProgressSink`]: the command line draws a bar), and the
//! only place the film is written.

use crate::accel::PACKET;
use crate::cryptomatte::{Mattes, PixelSamples, Rank};
use crate::effects::{Analysis, EffectMode};
use crate::film::{Film, PixelAov, PixelWindow};
use crate::integrator::{CameraSample, RayCounts, Whitted};
use crate::math::{Ray, Vec2, Vec3, Vec4};
use crate::rng::SampleRng;
use crate::scene::{Interaction, Scene, SettingsError, World};
use rayon::prelude::*;

mod progress;
mod threads;

pub use progress::{CancelFlag, ProgressSink, TileProgress};
pub use threads::{MAX_THREADS_PER_CORE, worker_threads};

const TILE: u32 = 16;

/// How to render.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RenderOptions {
    /// Seed of every sample's random stream.
    pub seed: u64,
    /// Worker threads (`None`: one per core).
    pub threads: Option<usize>,
    /// Told how many tiles there are and when each is done (the command line draws a bar).
    pub progress: ProgressSink,
    /// Trace the centre rays that fill the depth, normal and id layers (default true; the CLI
    /// turns this off when it writes no EXR). Off, those layers keep their miss values.
    pub aov_layers: bool,
    /// Only what changes the image, or everything (the reference).
    pub effects: EffectMode,
    /// The pixels to render (`--crop`, `--pixel-bounds`); `None`: the whole image. The film
    /// holds just these, each exactly as in a render of the whole image.
    pub window: Option<PixelWindow>,
    /// Raised to stop early (Ctrl-C): tiles not yet started are skipped, the film keeps the
    /// finished ones and [`Rendered::unfinished_tiles`] counts the rest.
    pub cancel: CancelFlag,
    /// Cryptomatte `CryptoObject` and `CryptoMaterial` layers with this many ranks per pixel
    /// (`None`: none; [`crate::cryptomatte::DEFAULT_LEVELS`] is the specification's default).
    pub cryptomatte: Option<u32>,
    /// Camera rays that escape add neither the background colour nor alpha: A = 0 and RGB = 0
    /// where nothing was hit, for compositing over a plate. Reflected and refracted rays still
    /// see the background.
    pub transparent: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            seed: 0,
            threads: None,
            progress: ProgressSink::default(),
            aov_layers: true,
            effects: EffectMode::Auto,
            window: None,
            cancel: CancelFlag::default(),
            cryptomatte: None,
            transparent: false,
        }
    }
}

/// A finished render.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The image and its AOV layers.
    pub film: Film,
    /// Rays traced, by kind, and not traced, by reason.
    pub counts: RayCounts,
    /// What the render decided to simulate, and why.
    pub analysis: Analysis,
    /// Tiles skipped because the render was cancelled; their pixels keep the film's initial
    /// value (RGBA 0, so alpha 0, and the AOV miss values). 0 for a complete render.
    pub unfinished_tiles: usize,
    /// Tiles in the render (finished or not).
    pub tiles: usize,
}

impl Rendered {
    /// True when the render was cancelled before every tile was done.
    pub fn is_partial(&self) -> bool {
        self.unfinished_tiles > 0
    }
}

/// Why a render could not run.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// A setting is outside what the renderer accepts ([`crate::scene::Settings::validate`]).
    #[error(transparent)]
    Settings(#[from] SettingsError),
    /// The pixel bounds are empty or reach outside the image.
    #[error("{0}")]
    Window(String),
    /// The thread pool could not start.
    #[error("could not start {0} worker threads: {1}")]
    Threads(usize, String),
}

struct TileResult {
    x0: u32,
    y0: u32,
    w: u32,
    pixels: Vec<(Vec4, PixelAov)>,
    /// Object then material ranks, `levels` per pixel (empty without Cryptomatte).
    crypto: [Vec<Rank>; 2],
    counts: RayCounts,
}

/// Renders `world`'s scene through its accelerator.
/// The image and the ray counts are identical for any thread count.
pub fn render(world: &World, opts: &RenderOptions) -> Result<Rendered, RenderError> {
    let scene = world.scene();
    let st = scene.settings();
    let (width, height) = (st.width, st.height);
    // Whatever set them (a scene file, a flag, library code), these bound the work per pixel
    // and the recursion depth of the integrator (each bounce is a stack frame).
    st.validate()?;
    let window = opts.window.unwrap_or(PixelWindow::full(width, height));
    window.check(width, height).map_err(RenderError::Window)?;
    // Tiles on the full image's 16-pixel grid, clipped to the window.
    let (tx0, ty0) = (window.x0 / TILE, window.y0 / TILE);
    let (tx1, ty1) = (window.x1.div_ceil(TILE), window.y1.div_ceil(TILE));
    let tiles: Vec<(u32, u32)> = (ty0..ty1)
        .flat_map(|ty| (tx0..tx1).map(move |tx| (tx * TILE, ty * TILE)))
        .collect();
    let bar = &opts.progress;
    bar.start(tiles.len() as u64);
    let analysis = Analysis::new(scene, opts.effects, opts.aov_layers);
    let integrator = Whitted::new(world, &analysis);
    let pixels = window.width() as usize * window.height() as usize;
    let mut mattes = opts
        .cryptomatte
        .map(|levels| scene_mattes(scene, levels, pixels));
    let pass = Pass {
        scene,
        integrator: &integrator,
        seed: opts.seed,
        lens_rays: analysis.lens_rays,
        aov: analysis.aov.on,
        window,
        mattes: mattes.as_ref(),
        transparent: opts.transparent,
    };
    let run = || -> Vec<TileResult> {
        tiles
            .par_iter()
            .filter_map(|&(x0, y0)| {
                if opts.cancel.is_raised() {
                    return None;
                }
                let tile = pass.tile(x0, y0);
                bar.tile_done();
                Some(tile)
            })
            .collect()
    };
    let results = match opts.threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| RenderError::Threads(n, e.to_string()))?
            .install(run),
        None => run(),
    };
    bar.finish();
    let mut film = Film::window(width, height, window);
    let mut counts = RayCounts::default();
    let unfinished_tiles = tiles.len() - results.len();
    let (ox, oy) = film.origin();
    let film_width = window.width();
    for t in results {
        counts += t.counts;
        for (i, (rgba, aov)) in t.pixels.into_iter().enumerate() {
            let (x, y) = (t.x0 + i as u32 % t.w - ox, t.y0 + i as u32 / t.w - oy);
            film.set(x, y, rgba, aov);
            if let Some(m) = &mut mattes {
                let n = m.levels();
                let [object, material] = &t.crypto;
                let at = (y * film_width + x) as usize;
                m.set_pixel(at, &object[i * n..][..n], &material[i * n..][..n]);
            }
        }
    }
    for layer in mattes.into_iter().flat_map(Mattes::into_layers) {
        film.add_crypto(layer);
    }
    Ok(Rendered {
        film,
        counts,
        analysis,
        unfinished_tiles,
        tiles: tiles.len(),
    })
}

/// Empty Cryptomatte layers named after `scene`'s objects and materials.
fn scene_mattes(scene: &Scene, levels: u32, pixels: usize) -> Mattes {
    let objects: Vec<&str> = scene.objects().iter().map(|o| o.name.as_str()).collect();
    let materials: Vec<&str> = scene.material_names().iter().map(String::as_str).collect();
    let object_material: Vec<u32> = scene.objects().iter().map(|o| o.material).collect();
    Mattes::new(&objects, &materials, object_material, levels, pixels)
}

/// What every pixel of one render shares.
struct Pass<'a> {
    scene: &'a Scene,
    integrator: &'a Whitted<'a>,
    seed: u64,
    /// Lens rays per pixel sample (1 on a pinhole camera).
    lens_rays: u32,
    /// Whether centre rays for the AOV layers are traced.
    aov: bool,
    /// The pixels rendered.
    window: PixelWindow,
    /// The Cryptomatte layers being made, if any (read here only for their ids).
    mattes: Option<&'a Mattes>,
    /// Escaping camera rays add nothing (see [`RenderOptions::transparent`]).
    transparent: bool,
}

impl Pass<'_> {
    /// The pixels of the tile at `(x0, y0)` inside the window.
    fn tile(&self, x0: u32, y0: u32) -> TileResult {
        let w = self.window;
        // (x0, y0) is on the tile grid: the tile ends a TILE later, clipped like its start.
        let (x1, y1) = ((x0 + TILE).min(w.x1), (y0 + TILE).min(w.y1));
        let (x0, y0) = (x0.max(w.x0), y0.max(w.y0));
        let mut counts = RayCounts::default();
        let n = ((x1 - x0) * (y1 - y0)) as usize;
        let mut pixels = Vec::with_capacity(n);
        let levels = self.mattes.map_or(0, Mattes::levels);
        let mut crypto = [
            vec![Rank::default(); n * levels],
            vec![Rank::default(); n * levels],
        ];
        let mut samples = PixelSamples::default();
        let mut rays = Vec::new();
        for (i, (x, y)) in (y0..y1)
            .flat_map(|y| (x0..x1).map(move |x| (x, y)))
            .enumerate()
        {
            pixels.push(self.pixel(x, y, &mut samples, &mut rays, &mut counts));
            if let Some(m) = self.mattes {
                let st = self.scene.settings();
                let total = st.spp * st.spp * self.lens_rays;
                let [object, material] = &mut crypto;
                let (object, material) = (
                    &mut object[i * levels..][..levels],
                    &mut material[i * levels..][..levels],
                );
                m.rank(&mut samples, total, object, material);
            }
        }
        TileResult {
            x0,
            y0,
            w: x1 - x0,
            pixels,
            crypto,
            counts,
        }
    }

    /// `spp x spp` stratified samples (each jittered in its stratum), each traced through
    /// `lens_rays` lens positions, box-filtered; plus one pinhole ray through the pixel centre
    /// for the AOV layers when they are written. The first-hit object of every camera ray goes
    /// to `samples` when Cryptomatte layers are made.
    fn pixel(
        &self,
        x: u32,
        y: u32,
        samples: &mut PixelSamples,
        rays: &mut Vec<Ray>,
        counts: &mut RayCounts,
    ) -> (Vec4, PixelAov) {
        let st = self.scene.settings();
        let cam = self.scene.camera();
        let frame = self.integrator.world().accel().frame();
        let n = st.spp;
        // Every camera ray of the pixel, in sample order, then traced in packets (the samples
        // of one pixel are the most coherent rays there are) and summed in the same order.
        rays.clear();
        for s in 0..n * n {
            let mut rng = SampleRng::new(self.seed, x, y, s);
            let jitter = Vec2::new(rng.next_f32(), rng.next_f32());
            let stratum = Vec2::new((s % n) as f32, (s / n) as f32);
            let film = Vec2::new(x as f32, y as f32) + (stratum + jitter) / n as f32;
            for _ in 0..self.lens_rays {
                let lens = Vec2::new(rng.next_f32(), rng.next_f32());
                rays.push(cam.ray(frame, film, st.width, st.height, lens));
            }
        }
        counts.not_traced.lens +=
            u64::from(n * n) * u64::from(st.lens_samples.saturating_sub(self.lens_rays));
        let mut sum = Vec4::ZERO;
        let mut traced = [CameraSample::default(); PACKET];
        for packet in rays.chunks(PACKET) {
            let traced = &mut traced[..packet.len()];
            self.integrator.camera_rays(packet, counts, traced);
            for sample in traced.iter() {
                match sample.object {
                    Some(object) if self.mattes.is_some() => samples.add(object),
                    None if self.transparent => continue,
                    _ => {}
                }
                sum += sample
                    .radiance
                    .extend(if sample.opaque { 1.0 } else { 0.0 });
            }
        }
        let rgba = sum / (n * n * self.lens_rays) as f32;
        let aov = if self.aov {
            centre_aov(self.scene, self.integrator, x, y, counts)
        } else {
            counts.not_traced.aov += 1;
            PixelAov::MISS
        };
        (rgba, aov)
    }
}
/// What the pinhole ray through the centre of pixel `(x, y)` hits: exactly the ray a compositor
/// rebuilds from the EXR's `worldToNDC`.
fn centre_aov(
    scene: &Scene,
    integrator: &Whitted,
    x: u32,
    y: u32,
    counts: &mut RayCounts,
) -> PixelAov {
    let st = scene.settings();
    let cam = scene.camera();
    let ray = cam.centre_ray(
        integrator.world().accel().frame(),
        Vec2::new(x as f32 + 0.5, y as f32 + 0.5),
        st.width,
        st.height,
    );
    counts.aov += 1;
    let world = integrator.world();
    let Some(traced) = world.trace(&ray, &mut counts.traversal) else {
        return PixelAov::MISS;
    };
    // Texture coordinates always, for the uv layer (shading computes them only where a
    // texture reads them).
    let Interaction {
        prim,
        object,
        surface: s,
        ..
    } = world.interaction(&traced, true);
    let m = scene.material_of(object);
    // A textured material's albedo is the one shading uses at this hit.
    let albedo = match m.textured {
        Some(_) => m
            .at_hit(&scene.geometry().hit_attributes(prim, &s), s.ns, s.ng)
            .map_or(Vec3::ZERO, |a| a.material.diffuse.eval(s.p, s.uv)),
        None => m.diffuse.eval(s.p, s.uv),
    };
    // The normal is reported as the surface defines it (outward / winding), not flipped
    // towards the camera, so it compares directly with other engines' normals.
    PixelAov {
        depth: (s.p - cam.position()).dot(cam.forward()),
        normal: s.ns,
        prim_id: prim as i32,
        object_id: object as i32,
        albedo,
        position: s.p,
        uv: s.uv,
    }
}
