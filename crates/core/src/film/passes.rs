//! The film's RGB pass layers: the light-path passes (`diffuse`, `specular`, ...), one per
//! light (`light.<name>`) and the shadow catcher's `shadow`, box-filtered over each pixel's
//! samples exactly as the beauty is.

use super::Film;
use crate::math::Vec3;

/// One RGB pass of the film.
#[derive(Clone, Debug, PartialEq)]
pub struct PassLayer {
    name: String,
    values: Vec<Vec3>,
    colour: bool,
}

impl PassLayer {
    /// A pass named `name` (lumis's layer name: `diffuse`, `light.key`, `shadow`) of
    /// `pixels` zeros; `colour` passes are radiance and take the exposure with the beauty,
    /// others (the shadow multiplier) do not.
    pub fn new(name: impl Into<String>, pixels: usize, colour: bool) -> Self {
        Self {
            name: name.into(),
            values: vec![Vec3::ZERO; pixels],
            colour,
        }
    }

    /// The layer name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// One value per pixel, row-major.
    pub fn values(&self) -> &[Vec3] {
        &self.values
    }

    /// Mutable values.
    pub fn values_mut(&mut self) -> &mut [Vec3] {
        &mut self.values
    }

    /// Whether the pass is radiance (scaled by the exposure).
    pub fn is_colour(&self) -> bool {
        self.colour
    }
}

/// Whether the lumis layer `name` is a radiance pass (every pass but `shadow`, which
/// multiplies a plate).
pub fn is_colour_pass(name: &str) -> bool {
    name != SHADOW_PASS
}

/// The shadow catcher's pass: what a plate is multiplied by (1 where there is no shadow).
pub const SHADOW_PASS: &str = "shadow";

impl Film {
    /// The pass layers, in the order they were added.
    pub fn passes(&self) -> &[PassLayer] {
        &self.passes
    }

    /// Adds a pass layer; it must have one value per pixel of the film.
    pub fn add_pass(&mut self, layer: PassLayer) {
        assert_eq!(
            layer.values.len(),
            self.rgba.len(),
            "pass {} made for another film size",
            layer.name
        );
        self.passes.push(layer);
    }

    /// Mutable pass layers, for the renderer to fill.
    pub fn passes_mut(&mut self) -> &mut [PassLayer] {
        &mut self.passes
    }
}
