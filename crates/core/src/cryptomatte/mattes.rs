//! The two Cryptomatte types lumis writes, `CryptoObject` and `CryptoMaterial`, made for one
//! scene, and the per-pixel gathering of the samples' first hits that feeds them.

use super::{CryptoLayer, Rank};

/// Type name of the object mattes (the objects' names).
pub const CRYPTO_OBJECT: &str = "CryptoObject";
/// Type name of the material mattes (the materials' names).
pub const CRYPTO_MATERIAL: &str = "CryptoMaterial";

/// The object and material layers of a scene and the object → material map the sampler needs.
#[derive(Clone, Debug)]
pub struct Mattes {
    object: CryptoLayer,
    material: CryptoLayer,
    object_material: Vec<u32>,
}

impl Mattes {
    /// Empty layers with `levels` ranks for each of `pixels` pixels, named after a scene's
    /// `objects` and `materials`; `object_material[o]` is object `o`'s material index.
    pub fn new(
        objects: &[&str],
        materials: &[&str],
        object_material: Vec<u32>,
        levels: u32,
        pixels: usize,
    ) -> Self {
        // Loaders add materials no object ends up with (an OBJ's default, unused MTL
        // entries): listing them would offer empty mattes.
        let mut used = vec![false; materials.len()];
        for &m in &object_material {
            used[m as usize] = true;
        }
        let used = |m: usize| used[m];
        Self {
            object: CryptoLayer::new(CRYPTO_OBJECT, objects, levels, pixels),
            material: CryptoLayer::listing(CRYPTO_MATERIAL, materials, used, levels, pixels),
            object_material,
        }
    }

    /// Ranks per pixel.
    pub fn levels(&self) -> usize {
        self.object.levels()
    }

    /// Ranks the pixel gathered in `samples` (of `total` samples in all) into `object` and
    /// `material` (`levels` entries each).
    pub fn rank(
        &self,
        samples: &mut PixelSamples,
        total: u32,
        object: &mut [Rank],
        material: &mut [Rank],
    ) {
        samples.scratch.clear();
        samples.scratch.extend(
            samples
                .objects
                .iter()
                .map(|&(o, w)| (self.object_material[o as usize], w)),
        );
        self.object.rank_pixel(&mut samples.objects, total, object);
        self.material
            .rank_pixel(&mut samples.scratch, total, material);
        samples.objects.clear();
    }

    /// Stores the ranks of pixel `i` in both layers.
    pub fn set_pixel(&mut self, i: usize, object: &[Rank], material: &[Rank]) {
        self.object.set_pixel(i, object);
        self.material.set_pixel(i, material);
    }

    /// The finished layers, objects first.
    pub fn into_layers(self) -> [CryptoLayer; 2] {
        [self.object, self.material]
    }
}

/// The first-hit objects of one pixel's camera samples. Kept per tile and cleared by
/// [`Mattes::rank`], so a render allocates it once per tile, not per pixel.
#[derive(Clone, Debug, Default)]
pub struct PixelSamples {
    objects: Vec<(u32, u32)>,
    scratch: Vec<(u32, u32)>,
}

impl PixelSamples {
    /// Counts one sample of weight 1 whose camera ray hit `object` first.
    pub fn add(&mut self, object: u32) {
        // Consecutive samples (the lens rays of one film sample) often hit the same object.
        match self.objects.last_mut() {
            Some((o, w)) if *o == object => *w += 1,
            _ => self.objects.push((object, 1)),
        }
    }
}
