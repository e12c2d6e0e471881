//! The Cryptomatte layers of the merged film: each tile lists the names its pixels may carry,
//! and the merged layer lists them all. lumis's manifests list the scene's names, so the
//! tiles' are equal; a name with two ids would mean two different scenes, and is refused.

use std::collections::BTreeMap;

use super::tile::TileFile;
use crate::farm::FarmError;
use crate::output::CryptoHeader;
use lumis_core::cryptomatte::{CryptoLayer, Rank};

/// The layers of the full `pixels`-pixel film, empty, with the union of the tiles' manifests.
/// The tiles' layers agree in names and levels (their channel lists were compared).
pub fn merged_layers(tiles: &[TileFile], pixels: usize) -> Result<Vec<CryptoLayer>, FarmError> {
    let first = &tiles[0];
    let mut merged: Vec<CryptoHeader> = first.file.header().crypto.clone();
    for tile in &tiles[1..] {
        for layer in &tile.file.header().crypto {
            let Some(into) = merged.iter_mut().find(|m| m.name == layer.name) else {
                continue;
            };
            union(&mut into.manifest, &layer.manifest).map_err(|(name, here, there)| {
                FarmError::Mismatch {
                    path: tile.path().to_path_buf(),
                    first: first.path().to_path_buf(),
                    what: format!("the Cryptomatte manifest of {}", layer.name),
                    detail: format!("{name:?} has id {here:08x} here and {there:08x} elsewhere"),
                }
            })?;
        }
    }
    merged
        .into_iter()
        .map(|m| {
            let mut ranks = Vec::new();
            let n = pixels * m.levels as usize;
            ranks.try_reserve_exact(n).map_err(|_| FarmError::Format {
                path: first.path().to_path_buf(),
                message: format!("not enough memory for {pixels} pixels of layer {}", m.name),
            })?;
            ranks.resize(n, Rank::default());
            CryptoLayer::from_ranks(&m.name, m.manifest, m.levels, ranks).map_err(|message| {
                FarmError::Format {
                    path: first.path().to_path_buf(),
                    message,
                }
            })
        })
        .collect()
}

/// Adds `more` to `into`; the first name whose id differs, with its two ids, as the error.
fn union(
    into: &mut BTreeMap<String, u32>,
    more: &BTreeMap<String, u32>,
) -> Result<(), (String, u32, u32)> {
    for (name, &id) in more {
        match into.get(name) {
            Some(&earlier) if earlier != id => return Err((name.clone(), id, earlier)),
            Some(_) => {}
            None => {
                into.insert(name.clone(), id);
            }
        }
    }
    Ok(())
}
