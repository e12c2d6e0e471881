//! Cryptomatte: anti-aliased id mattes by name, as the open Cryptomatte specification (1.1.0)
//! defines them and Blender, Nuke, Arnold and V-Ray read and write them.
//!
//! Every camera sample of a pixel (each stratified film sample through each lens sample) adds
//! its weight to the id of the name its first hit carries; samples that hit nothing add to no
//! id. The ids of a pixel are ranked by their summed weight, normalised by the pixel's total
//! weight into coverage, and the first `levels` (id, coverage) pairs are kept. Where no more
//! than `levels` names meet in a pixel, its coverages sum to the fraction of samples that hit
//! something: the film's alpha when misses are transparent.
//!
//! ```text
//! lumis render scene.toml -o out.exr --cryptomatte --cryptomatte-levels 6
//! ```

pub mod hash;
mod mattes;

use std::collections::BTreeMap;

pub use hash::{id_bits, metadata_key, murmur3_32, name_id};
pub use mattes::{CRYPTO_MATERIAL, CRYPTO_OBJECT, Mattes, PixelSamples};

/// The specification's suggested number of ranks per pixel (3 RGBA layers of 2 pairs each).
pub const DEFAULT_LEVELS: u32 = 6;
/// The most ranks a layer may keep: 64 RGBA layers of float32 is already 1 KiB per pixel.
pub const MAX_LEVELS: u32 = 128;

/// One ranked entry of a pixel: the id's float bits and its share of the pixel's weight.
/// An empty rank is id 0 with coverage 0, as the specification asks for "no object".
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rank {
    /// Bits of the float32 id ([`id_bits`] of the name's hash).
    pub id: u32,
    /// Summed sample weight of the id over the pixel's total sample weight, in [0, 1].
    pub coverage: f32,
}

/// One Cryptomatte type (`CryptoObject`, `CryptoMaterial`): its name, the id of every scene
/// index (object or material), the manifest and `levels` ranks per pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct CryptoLayer {
    name: String,
    ids: Vec<u32>,
    manifest: BTreeMap<String, u32>,
    levels: usize,
    ranks: Vec<Rank>,
}

impl CryptoLayer {
    /// A layer called `name` over the scene indices named `names` (index `i` is `names[i]`),
    /// with `levels` ranks for each of `pixels` pixels, all empty. Equal names share an id
    /// (the specification's grouping: two objects called "tree" are one matte).
    pub fn new(name: &str, names: &[&str], levels: u32, pixels: usize) -> Self {
        Self::listing(name, names, |_| true, levels, pixels)
    }

    /// [`Self::new`] with only the indices `listed` accepts in the manifest: the names a
    /// pixel can carry (materials no object uses would be empty mattes in a compositor's list).
    pub fn listing(
        name: &str,
        names: &[&str],
        listed: impl Fn(usize) -> bool,
        levels: u32,
        pixels: usize,
    ) -> Self {
        let levels = levels.clamp(1, MAX_LEVELS) as usize;
        let ids = names
            .iter()
            .map(|n| id_bits(murmur3_32(n.as_bytes())))
            .collect::<Vec<_>>();
        let manifest = (names.iter().zip(&ids).enumerate())
            .filter(|&(i, _)| listed(i))
            .map(|(_, (n, &id))| (n.to_string(), id));
        Self {
            name: name.to_string(),
            manifest: manifest.collect(),
            ids,
            levels,
            ranks: vec![Rank::default(); levels * pixels],
        }
    }

    /// A layer rebuilt from what a file recorded (an EXR read back): its type name, manifest,
    /// `levels` ranks per pixel and every pixel's ranks. The scene indices are not in a file,
    /// so such a layer has no [`Self::id_of`] (it ranks nothing; it is written again).
    pub fn from_ranks(
        name: &str,
        manifest: BTreeMap<String, u32>,
        levels: u32,
        ranks: Vec<Rank>,
    ) -> Result<Self, String> {
        if !(1..=MAX_LEVELS).contains(&levels) {
            return Err(format!(
                "Cryptomatte layer {name}: {levels} ranks per pixel, expected 1..={MAX_LEVELS}"
            ));
        }
        let levels = levels as usize;
        if !ranks.len().is_multiple_of(levels) {
            return Err(format!(
                "Cryptomatte layer {name}: {} ranks are no whole number of pixels of {levels}",
                ranks.len()
            ));
        }
        Ok(Self {
            name: name.to_string(),
            ids: Vec::new(),
            manifest,
            levels,
            ranks,
        })
    }

    /// The type name (`CryptoObject`), the prefix of the layer's channels.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Ranks per pixel.
    pub fn levels(&self) -> usize {
        self.levels
    }

    /// The id bits of scene index `index` (a layer made by [`Self::new`] or [`Self::listing`];
    /// one rebuilt by [`Self::from_ranks`] knows no scene indices).
    pub fn id_of(&self, index: u32) -> u32 {
        self.ids[index as usize]
    }

    /// Name to id bits, sorted by name.
    pub fn manifest(&self) -> &BTreeMap<String, u32> {
        &self.manifest
    }

    /// The manifest as the specification's JSON: `{"name":"8 hex digits of the float",...}`.
    pub fn manifest_json(&self) -> String {
        let map: serde_json::Map<String, serde_json::Value> = self
            .manifest
            .iter()
            .map(|(n, id)| (n.clone(), format!("{id:08x}").into()))
            .collect();
        serde_json::Value::Object(map).to_string()
    }

    /// The ranks of pixel `i` (row-major from the top-left), best first.
    pub fn pixel(&self, i: usize) -> &[Rank] {
        &self.ranks[i * self.levels..(i + 1) * self.levels]
    }

    /// Every pixel's ranks, `levels` per pixel.
    pub fn ranks(&self) -> &[Rank] {
        &self.ranks
    }

    /// Stores the ranks of pixel `i` (`ranks.len() == levels`).
    pub fn set_pixel(&mut self, i: usize, ranks: &[Rank]) {
        self.ranks[i * self.levels..(i + 1) * self.levels].copy_from_slice(ranks);
    }

    /// Ranks one pixel into `out` (`levels` entries): `hits` holds `(scene index, weight)`
    /// per hit sample group, in any order, and is reordered in place; `total` is the summed
    /// weight of all the pixel's samples, misses included.
    ///
    /// Weights are integers (every sample of the box filter weighs the same), so summing them
    /// is exact and the result does not depend on the order the samples came in. Ties are
    /// broken by the id bits, so the ranking is a function of the pixel's samples alone.
    pub fn rank_pixel(&self, hits: &mut Vec<(u32, u32)>, total: u32, out: &mut [Rank]) {
        // Indices to ids, then equal ids (same name) merged.
        for h in hits.iter_mut() {
            h.0 = self.id_of(h.0);
        }
        hits.sort_unstable();
        hits.dedup_by(|next, kept| {
            let same = next.0 == kept.0;
            if same {
                kept.1 += next.1;
            }
            same
        });
        hits.sort_unstable_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        out.fill(Rank::default());
        for (slot, &(id, weight)) in out.iter_mut().zip(hits.iter()) {
            *slot = Rank {
                id,
                coverage: weight as f32 / total as f32,
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranking_is_by_coverage_then_id_and_merges_equal_names() {
        let layer = CryptoLayer::new("CryptoObject", &["a", "b", "a", "c"], 3, 1);
        let mut out = [Rank::default(); 3];
        // "a" twice (indices 0 and 2) outweighs "b"; "c" ties with "b".
        let mut hits = vec![(1, 3), (2, 2), (3, 3), (0, 2)];
        layer.rank_pixel(&mut hits, 10, &mut out);
        assert_eq!(
            out[0],
            Rank {
                id: layer.id_of(0),
                coverage: 0.4
            }
        );
        let (b, c) = (layer.id_of(1), layer.id_of(3));
        assert_eq!([out[1].id, out[2].id], [b.min(c), b.max(c)]);
        assert_eq!(out[1].coverage, 0.3);
        assert_eq!(layer.manifest().len(), 3);
    }

    #[test]
    fn empty_ranks_are_zero_and_extra_ids_are_dropped() {
        let layer = CryptoLayer::new("CryptoMaterial", &["m0", "m1", "m2"], 2, 1);
        let mut out = [Rank {
            id: 7,
            coverage: 1.0,
        }; 2];
        layer.rank_pixel(&mut Vec::new(), 4, &mut out);
        assert_eq!(out, [Rank::default(); 2]);
        let mut hits = vec![(0, 1), (1, 2), (2, 1)];
        layer.rank_pixel(&mut hits, 4, &mut out);
        assert_eq!(
            out[0],
            Rank {
                id: layer.id_of(1),
                coverage: 0.5
            }
        );
        assert_eq!(out[1].coverage, 0.25);
    }

    #[test]
    fn listing_leaves_unused_names_out_of_the_manifest_only() {
        let layer = CryptoLayer::listing("CryptoMaterial", &["a", "b", "c"], |i| i != 1, 2, 1);
        let names: Vec<&str> = layer.manifest().keys().map(String::as_str).collect();
        assert_eq!(names, ["a", "c"]);
        // The unlisted index still has its id (it is simply never hit).
        assert_eq!(layer.id_of(1), id_bits(murmur3_32(b"b")));
    }

    #[test]
    fn a_layer_rebuilt_from_its_ranks_equals_in_what_a_file_holds() {
        let mut layer = CryptoLayer::new("CryptoObject", &["a", "b"], 2, 3);
        let r = Rank {
            id: layer.id_of(1),
            coverage: 0.5,
        };
        layer.set_pixel(2, &[r, Rank::default()]);
        let back = CryptoLayer::from_ranks(
            layer.name(),
            layer.manifest().clone(),
            2,
            layer.ranks().to_vec(),
        )
        .unwrap();
        assert_eq!(back.pixel(2), layer.pixel(2));
        assert_eq!(back.manifest_json(), layer.manifest_json());
        assert!(CryptoLayer::from_ranks("C", BTreeMap::new(), 0, vec![]).is_err());
        assert!(CryptoLayer::from_ranks("C", BTreeMap::new(), 2, vec![r; 3]).is_err());
    }

    #[test]
    fn manifest_is_json_with_the_float_bits_in_hex() {
        let layer = CryptoLayer::new("CryptoAsset", &["bunny", "default"], 6, 0);
        assert_eq!(
            layer.manifest_json(),
            r#"{"bunny":"13851a76","default":"42c9679f"}"#
        );
    }
}
