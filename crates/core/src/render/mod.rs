//! Drives the integrator over the image: rayon over 16x16 tiles, stratified jittered samples,
//! progress reported to whoever listens ([`ProgressSink`]: the command line draws a bar), and the
//! only place the film is written.

use crate::accel::PACKET;
use crate::cryptomatte::{Mattes, PixelSamples, Rank};
use crate::effects::{Analysis, EffectMode};
use crate::film::{Film, PassLayer, PixelAov, PixelWindow};
use crate::integrator::{CameraSample, RayCounts, Split, Whitted};
use crate::math::{Ray, Vec2, Vec3, Vec4};
use crate::rng::SampleRng;
use crate::scene::{Scene, SettingsError, World};
use rayon::prelude::*;

mod adaptive;
mod centre;
mod passes;
mod progress;
mod threads;

use adaptive::BasePass;
pub use adaptive::base_strata;
use centre::centre_aov;
use passes::PassLayout;
pub use passes::PassRequest;
pub use progress::{CancelFlag, ProgressSink, TilePixels, TileProgress};
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
    /// The RGB pass layers to fill besides the beauty.
    pub passes: PassRequest,
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
            passes: PassRequest::default(),
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
    /// The pass values, `PassNames::count` per pixel (empty without passes).
    passes: Vec<Vec3>,
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
    let integrator = Whitted::new(world, &analysis).with_transparent(opts.transparent);
    let layout = PassLayout::new(scene, opts.passes);
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
        layout: &layout,
    };
    let run = || -> (Vec<TileResult>, RayCounts) {
        // Adaptive: every decision reads the base pass of the window and a one-pixel border,
        // made first, so that no tile split, crop or thread count changes one.
        let base = match st.adaptive {
            Some(threshold) => match BasePass::trace(&pass, threshold, &opts.cancel) {
                Some(base) => Some(base),
                None => return (Vec::new(), RayCounts::default()),
            },
            None => None,
        };
        let tiles = tiles
            .par_iter()
            .filter_map(|&(x0, y0)| {
                if opts.cancel.is_raised() {
                    return None;
                }
                let tile = match &base {
                    Some(base) => pass.tile(x0, y0, |x, y, scratch, counts, passes| {
                        base.pixel(&pass, x, y, scratch, counts, passes)
                    }),
                    None => pass.tile(x0, y0, |x, y, scratch, counts, passes| {
                        pass.pixel(x, y, scratch, counts, passes)
                    }),
                };
                bar.tile_done(&TilePixels::new((tile.x0, tile.y0), tile.w, &tile.pixels));
                Some(tile)
            })
            .collect();
        (tiles, base.map_or(RayCounts::default(), |b| b.counts))
    };
    let (results, base_counts) = match opts.threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| RenderError::Threads(n, e.to_string()))?
            .install(run),
        None => run(),
    };
    bar.finish();
    let mut film = Film::window(width, height, window);
    let mut counts = base_counts;
    let unfinished_tiles = tiles.len() - results.len();
    let (ox, oy) = film.origin();
    let film_width = window.width();
    for (name, colour) in layout.names() {
        film.add_pass(PassLayer::new(name, pixels, colour));
    }
    let k = layout.count();
    for t in results {
        counts += t.counts;
        for (i, (rgba, aov)) in t.pixels.into_iter().enumerate() {
            let (x, y) = (t.x0 + i as u32 % t.w - ox, t.y0 + i as u32 / t.w - oy);
            film.set(x, y, rgba, aov);
            let at = (y * film_width + x) as usize;
            for (pass, v) in film.passes_mut().iter_mut().zip(&t.passes[i * k..][..k]) {
                pass.values_mut()[at] = *v;
            }
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
    /// The pass layers being filled.
    layout: &'a PassLayout,
}

impl Pass<'_> {
    /// The pixels of the tile at `(x0, y0)` inside the window, each made by `pixel` (its
    /// colour, centre-ray AOV and the pixel samples it took).
    fn tile(
        &self,
        x0: u32,
        y0: u32,
        mut pixel: impl FnMut(u32, u32, &mut Scratch, &mut RayCounts, &mut [Vec3]) -> (Vec4, PixelAov),
    ) -> TileResult {
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
        let mut scratch = Scratch::default();
        let k = self.layout.count();
        let mut passes = vec![Vec3::ZERO; n * k];
        for (i, (x, y)) in (y0..y1)
            .flat_map(|y| (x0..x1).map(move |x| (x, y)))
            .enumerate()
        {
            let out = &mut passes[i * k..][..k];
            let (rgba, aov) = pixel(x, y, &mut scratch, &mut counts, out);
            pixels.push((rgba, aov));
            if let Some(m) = self.mattes {
                let total = aov.samples * self.lens_rays;
                let [object, material] = &mut crypto;
                let (object, material) = (
                    &mut object[i * levels..][..levels],
                    &mut material[i * levels..][..levels],
                );
                m.rank(&mut scratch.samples, total, object, material);
            }
        }
        TileResult {
            x0,
            y0,
            w: x1 - x0,
            pixels,
            passes,
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
        scratch: &mut Scratch,
        counts: &mut RayCounts,
        passes: &mut [Vec3],
    ) -> (Vec4, PixelAov) {
        let st = self.scene.settings();
        let n = st.spp;
        let Scratch { samples, rays, .. } = scratch;
        // Every camera ray of the pixel, in sample order, then traced in packets (the samples
        // of one pixel are the most coherent rays there are) and summed in the same order.
        rays.clear();
        for s in 0..n * n {
            self.sample_rays(x, y, s, rays);
        }
        counts.not_traced.lens +=
            u64::from(n * n) * u64::from(st.lens_samples.saturating_sub(self.lens_rays));
        let mut sum = Vec4::ZERO;
        let mut add = |sample: &CameraSample, samples: &mut PixelSamples| {
            if let (Some(object), Some(_)) = (sample.object, self.mattes) {
                samples.add(object);
            }
            sum += sample.radiance.extend(sample.alpha);
        };
        if self.layout.splits() {
            // Split samples are traced one by one (the same samples as in packets).
            let lights = self.scene.lights().len();
            let mut per_light = vec![Vec3::ZERO; lights];
            for ray in rays.iter() {
                let mut split = Split::new(&mut per_light);
                let sample = self.integrator.camera_ray_split(ray, counts, &mut split);
                add(&sample, samples);
                self.layout.accumulate(&split, passes);
            }
        } else {
            let mut traced = [CameraSample::default(); PACKET];
            for packet in rays.chunks(PACKET) {
                let traced = &mut traced[..packet.len()];
                self.integrator.camera_rays(packet, counts, traced);
                for sample in traced.iter() {
                    add(sample, samples);
                }
            }
        }
        let total = (n * n * self.lens_rays) as f32;
        for v in passes.iter_mut() {
            *v /= total;
        }
        let rgba = sum / total;
        (rgba, self.centre(x, y, n * n, counts))
    }

    /// The camera rays of pixel sample `s` of pixel `(x, y)`, one per lens position, onto
    /// `rays`: jittered in stratum `(s % spp, s / spp)` by the sample's own random stream.
    #[inline]
    fn sample_rays(&self, x: u32, y: u32, s: u32, rays: &mut Vec<Ray>) {
        let st = self.scene.settings();
        let cam = self.scene.camera();
        let frame = self.integrator.world().accel().frame();
        let n = st.spp;
        let mut rng = SampleRng::new(self.seed, x, y, s);
        let jitter = Vec2::new(rng.next_f32(), rng.next_f32());
        let stratum = Vec2::new((s % n) as f32, (s / n) as f32);
        let film = Vec2::new(x as f32, y as f32) + (stratum + jitter) / n as f32;
        for _ in 0..self.lens_rays {
            let lens = Vec2::new(rng.next_f32(), rng.next_f32());
            rays.push(cam.ray(frame, film, st.width, st.height, lens));
        }
    }

    /// The AOV of pixel `(x, y)` (its centre ray's, when the layers are written) and the
    /// pixel samples it took.
    fn centre(&self, x: u32, y: u32, samples: u32, counts: &mut RayCounts) -> PixelAov {
        let aov = if self.aov {
            centre_aov(self.scene, self.integrator, x, y, counts)
        } else {
            counts.not_traced.aov += 1;
            PixelAov::MISS
        };
        PixelAov { samples, ..aov }
    }
}

/// What one worker re-uses from pixel to pixel.
#[derive(Default)]
struct Scratch {
    /// The pixel's first hits, for Cryptomatte.
    samples: PixelSamples,
    /// The pixel's camera rays.
    rays: Vec<Ray>,
    /// The samples an adaptive pixel traces after its base pass.
    rest: adaptive::Traced,
}
