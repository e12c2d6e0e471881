//! Adaptive supersampling (`--adaptive T`, `render.adaptive`): a base pass takes a few of each
//! pixel's `spp x spp` samples ([`base_strata`]); a pixel takes the rest only where the
//! relative contrast among its own base samples, or between its base mean and a neighbour's,
//! reaches `T` ([`decide`]).
//!
//! Every base sample is exactly the sample the full render takes in that stratum (the same
//! random stream, the same lens rays), and a refined pixel sums all its samples in the full
//! render's order, so it holds the full render's value bit for bit; `T = 0` refines every
//! pixel and gives the full render's image. Decisions read only base samples, traced for the
//! window and a one-pixel border around it before any tile, so that no crop, tile split or
//! thread count changes one.

mod decide;

pub use decide::base_strata;
use decide::converged;

use super::{Pass, Scratch};
use crate::accel::PACKET;
use crate::film::{PixelAov, PixelWindow};
use crate::integrator::{CameraSample, RayCounts, Split};
use crate::math::{Ray, Vec3, Vec4};
use crate::render::CancelFlag;
use rayon::prelude::*;

/// The base samples of every pixel of the window and of the one-pixel border around it inside
/// the image.
pub(super) struct BasePass {
    threshold: f32,
    /// The base strata, ascending.
    strata: Vec<u32>,
    /// The pixels held: the window grown by one pixel each way, clipped to the image.
    area: PixelWindow,
    /// Camera samples per pixel of `area` (row-major), `strata.len() * lens_rays` each, in
    /// sample order.
    samples: Vec<CameraSample>,
    /// The pass values of each camera sample, the pass layout's count each (empty without
    /// passes).
    passes: Vec<Vec3>,
    /// The mean RGBA of each pixel's base samples.
    means: Vec<Vec4>,
    /// What the base pass traced.
    pub(super) counts: RayCounts,
}

/// One row of the base pass.
#[derive(Default)]
struct Row {
    traced: Traced,
    counts: RayCounts,
}

impl BasePass {
    /// Traces the base pass of `pass`'s window (rows in parallel); `None` if `cancel` was
    /// raised before it finished.
    pub(super) fn trace(pass: &Pass, threshold: f32, cancel: &CancelFlag) -> Option<Self> {
        let st = pass.scene.settings();
        let w = pass.window;
        let area = PixelWindow {
            x0: w.x0.saturating_sub(1),
            x1: (w.x1 + 1).min(st.width),
            y0: w.y0.saturating_sub(1),
            y1: (w.y1 + 1).min(st.height),
        };
        let strata = base_strata(st.spp);
        let rows: Vec<Option<Row>> = (area.y0..area.y1)
            .into_par_iter()
            .map(|y| {
                if cancel.is_raised() {
                    return None;
                }
                let mut row = Row::default();
                let mut rays = Vec::new();
                for x in area.x0..area.x1 {
                    pass.trace_strata(x, y, &strata, &mut rays, &mut row.counts, &mut row.traced);
                }
                Some(row)
            })
            .collect();
        let mut base = BasePass {
            threshold,
            strata,
            area,
            samples: Vec::new(),
            passes: Vec::new(),
            means: Vec::new(),
            counts: RayCounts::default(),
        };
        for row in rows {
            let row = row?;
            base.samples.extend(row.traced.samples);
            base.passes.extend(row.traced.passes);
            base.counts += row.counts;
        }
        let per_pixel = base.strata.len() * pass.lens_rays as usize;
        base.means = base
            .samples
            .chunks(per_pixel)
            .map(|s| rgba_sum(s) / per_pixel as f32)
            .collect();
        Some(base)
    }

    /// Where pixel `(x, y)` (inside `area`) is held.
    fn index(&self, x: u32, y: u32) -> usize {
        (y - self.area.y0) as usize * self.area.width() as usize + (x - self.area.x0) as usize
    }

    /// Pixel `(x, y)` of the window: its base samples alone where they agree with each other
    /// and with its neighbours', else all its samples; `passes` gets its pass values.
    pub(super) fn pixel(
        &self,
        pass: &Pass,
        x: u32,
        y: u32,
        scratch: &mut Scratch,
        counts: &mut RayCounts,
        passes: &mut [Vec3],
    ) -> (Vec4, PixelAov) {
        let st = pass.scene.settings();
        let n = st.spp;
        let lens = pass.lens_rays as usize;
        let k = pass.layout.count();
        let b = self.strata.len();
        let at = self.index(x, y);
        let base = &self.samples[at * b * lens..][..b * lens];
        let base_passes = &self.passes[at * b * lens * k..][..b * lens * k];
        let keep = b as u32 == n * n || {
            let mut own = [Vec4::ZERO; 4];
            for (o, s) in own.iter_mut().zip(base.chunks(lens)) {
                *o = rgba_sum(s) / lens as f32;
            }
            let mut neighbours = [Vec4::ZERO; 8];
            let mut found = 0;
            for (dx, dy) in NEIGHBOURS {
                let (nx, ny) = (x.wrapping_add_signed(dx), y.wrapping_add_signed(dy));
                if nx < st.width && ny < st.height {
                    neighbours[found] = self.means[self.index(nx, ny)];
                    found += 1;
                }
            }
            converged(
                self.threshold,
                &own[..b],
                self.means[at],
                &neighbours[..found],
            )
        };
        let Scratch {
            samples,
            rays,
            rest,
        } = scratch;
        rest.samples.clear();
        rest.passes.clear();
        let taken = if keep {
            b as u32
        } else {
            let others: Vec<u32> = (0..n * n).filter(|s| !self.strata.contains(s)).collect();
            pass.trace_strata(x, y, &others, rays, counts, rest);
            n * n
        };
        counts.not_traced.adaptive += u64::from(n * n - taken) * lens as u64;
        counts.not_traced.lens +=
            u64::from(taken) * u64::from(st.lens_samples.saturating_sub(pass.lens_rays));
        // Every sample taken, in the full render's order: base and traced now interleaved by
        // stratum.
        let mut sum = Vec4::ZERO;
        let (mut from_base, mut from_rest) = (0, 0);
        for s in 0..n * n {
            let (source, source_passes, i) = if self.strata.contains(&s) {
                from_base += 1;
                (base, base_passes, from_base - 1)
            } else if keep {
                continue;
            } else {
                from_rest += 1;
                (&rest.samples[..], &rest.passes[..], from_rest - 1)
            };
            for j in i * lens..(i + 1) * lens {
                let sample = &source[j];
                if let (Some(object), Some(_)) = (sample.object, pass.mattes) {
                    samples.add(object);
                }
                sum += sample.radiance.extend(sample.alpha);
                for (p, v) in passes.iter_mut().zip(&source_passes[j * k..][..k]) {
                    *p += *v;
                }
            }
        }
        let total = (taken as usize * lens) as f32;
        for v in passes.iter_mut() {
            *v /= total;
        }
        (sum / total, pass.centre(x, y, taken, counts))
    }
}

/// The eight neighbours of a pixel.
const NEIGHBOURS: [(i32, i32); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// The RGBA of `samples` summed in order.
fn rgba_sum(samples: &[CameraSample]) -> Vec4 {
    samples
        .iter()
        .fold(Vec4::ZERO, |sum, s| sum + s.radiance.extend(s.alpha))
}

/// Camera samples traced for one pixel, with their pass values.
#[derive(Default)]
pub(super) struct Traced {
    samples: Vec<CameraSample>,
    passes: Vec<Vec3>,
}

impl Pass<'_> {
    /// Traces pixel samples `strata` of pixel `(x, y)` (through `rays`) and appends each
    /// camera sample to `samples` and its pass values to `passes`: the very samples
    /// [`Pass::pixel`] takes.
    fn trace_strata(
        &self,
        x: u32,
        y: u32,
        strata: &[u32],
        rays: &mut Vec<Ray>,
        counts: &mut RayCounts,
        out: &mut Traced,
    ) {
        let Traced { samples, passes } = out;
        rays.clear();
        for &s in strata {
            self.sample_rays(x, y, s, rays);
        }
        if self.layout.splits() {
            let k = self.layout.count();
            let mut per_light = vec![Vec3::ZERO; self.scene.lights().len()];
            for ray in rays.iter() {
                let mut split = Split::new(&mut per_light);
                samples.push(self.integrator.camera_ray_split(ray, counts, &mut split));
                let at = passes.len();
                passes.resize(at + k, Vec3::ZERO);
                self.layout.accumulate(&split, &mut passes[at..]);
            }
        } else {
            let mut traced = [CameraSample::default(); PACKET];
            for packet in rays.chunks(PACKET) {
                let traced = &mut traced[..packet.len()];
                self.integrator.camera_rays(packet, counts, traced);
                samples.extend_from_slice(traced);
            }
        }
    }
}
