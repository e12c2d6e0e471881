//! The decoded channels of a file lumis wrote, back into a [`Film`] window: the inverse of
//! `write.rs`, channel by channel, so that writing the film again gives the same samples.
//!
//! What the writer derives is taken back to what it was derived from: `Z` at a pixel whose
//! centre ray missed (`id.prim` = -1) is the miss value (`--z-miss`), so the film gets the
//! miss depth `+inf` and the metadata that value; ids are floats holding integers; Blender's
//! `uv.A` is the hit flag, recomputed on write.

use std::borrow::Cow;
use std::collections::BTreeMap;

use ::exr::prelude::{AnyChannels, FlatSamples, Layer};

use super::{BASE_FLOAT_CHANNELS, ExrHeader, aov_layers};
use lumis_core::film::{Film, PassLayer, PixelAov, is_colour_pass};
use lumis_core::math::{Vec3, Vec4};

/// The film `layer` holds (the file's only layer, described by `header`) and the `Z` value
/// of its missed pixels (`+inf` when none missed).
pub(super) fn film(
    header: &ExrHeader,
    layer: &Layer<AnyChannels<FlatSamples>>,
) -> Result<(Film, f32), String> {
    let meta = &header.meta;
    let layout = meta.layout;
    let (full_w, full_h) = header.full_size;
    let window = header.window;
    let pixels = window.width() as usize * window.height() as usize;
    let by_name: BTreeMap<String, &FlatSamples> = layer
        .channel_data
        .list
        .iter()
        .map(|c| (c.name.to_string(), &c.sample_data))
        .collect();
    // Every channel as f32 (HALF RGBA widened, exactly), NaN refused.
    let channel = |lumis: &str| -> Result<Cow<'_, [f32]>, String> {
        let name = layout.channel(lumis);
        let values: Cow<'_, [f32]> = match by_name.get(&name) {
            Some(FlatSamples::F32(v)) => Cow::Borrowed(v),
            Some(FlatSamples::F16(v)) => Cow::Owned(v.iter().map(|h| h.to_f32()).collect()),
            _ => return Err(format!("no float channel {name}")),
        };
        if values.len() != pixels {
            return Err(format!(
                "channel {name} holds {} samples, not {pixels}",
                values.len()
            ));
        }
        if values.iter().any(|v| v.is_nan()) {
            return Err(format!("channel {name} holds NaN"));
        }
        Ok(values)
    };
    let rgba: Vec<Cow<'_, [f32]>> = ["R", "G", "B", "A"]
        .iter()
        .map(|c| channel(c))
        .collect::<Result<_, _>>()?;
    let base: Vec<Cow<'_, [f32]>> = BASE_FLOAT_CHANNELS
        .iter()
        .map(|c| channel(c))
        .collect::<Result<_, _>>()?;
    let [z, nx, ny, nz, prim, object] = &base[..] else {
        unreachable!("six base channels");
    };
    let aov_names = aov_layers::names(meta.aov_layers, layout);
    let aov_values: Vec<Cow<'_, [f32]>> = aov_names
        .iter()
        .map(|c| channel(c))
        .collect::<Result<_, _>>()?;
    let id = |values: &[f32], name: &str, i: usize| -> Result<i32, String> {
        let v = values[i];
        let n = v as i32;
        if n as f32 != v {
            return Err(format!(
                "channel {} holds {v}, not an index",
                layout.channel(name)
            ));
        }
        Ok(n)
    };

    let mut film = Film::window(full_w, full_h, window);
    let mut z_miss = None;
    let w = window.width() as usize;
    for i in 0..pixels {
        let prim_id = id(prim, "id.prim", i)?;
        let mut aov = PixelAov {
            depth: z[i],
            normal: Vec3::new(nx[i], ny[i], nz[i]),
            prim_id,
            object_id: id(object, "id.object", i)?,
            ..PixelAov::MISS
        };
        if prim_id < 0 {
            // The writer put the miss value here: one value for the whole file.
            match z_miss {
                None => z_miss = Some(z[i]),
                Some(m) if m.to_bits() == z[i].to_bits() => {}
                Some(m) => {
                    return Err(format!(
                        "channel {} holds two values ({m} and {}) where the centre ray \
                         missed; lumis writes one",
                        layout.channel("Z"),
                        z[i]
                    ));
                }
            }
            aov.depth = f32::INFINITY;
        }
        for (name, values) in aov_names.iter().zip(&aov_values) {
            // An index channel holds integers: anything else would not be written back as read.
            if name.starts_with("id.") {
                id(values, name, i)?;
            }
            aov_layers::store(&mut aov, name, values[i]);
        }
        let colour = Vec4::new(rgba[0][i], rgba[1][i], rgba[2][i], rgba[3][i]);
        film.set((i % w) as u32, (i / w) as u32, colour, aov);
    }
    for name in &header.passes {
        let rgb = ["R", "G", "B"]
            .iter()
            .map(|c| channel(&format!("{name}.{c}")))
            .collect::<Result<Vec<_>, _>>()?;
        let mut layer = PassLayer::new(name, pixels, is_colour_pass(name));
        for (i, v) in layer.values_mut().iter_mut().enumerate() {
            *v = Vec3::new(rgb[0][i], rgb[1][i], rgb[2][i]);
        }
        film.add_pass(layer);
    }
    for crypto in &header.crypto {
        let names = crypto.channels(layout);
        let values = names
            .iter()
            .map(|name| match by_name.get(name) {
                Some(FlatSamples::F32(v)) if v.len() == pixels => Ok(v.as_slice()),
                _ => Err(format!("no float channel {name} of {pixels} samples")),
            })
            .collect::<Result<Vec<&[f32]>, String>>()?;
        film.add_crypto(crypto.layer(&values, pixels)?);
    }
    // What the writer would refuse, refused here, naming this file.
    lumis_core::film::check_finite(&film).map_err(|e| {
        format!(
            "{} non-finite sample(s), the first in channel {} at pixel ({}, {})",
            e.count, e.channel, e.x, e.y
        )
    })?;
    Ok((film, z_miss.unwrap_or(f32::INFINITY)))
}
