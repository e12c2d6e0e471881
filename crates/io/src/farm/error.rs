//! What can stop `lumis merge`, each naming the tile file at fault.

use std::path::PathBuf;

use lumis_core::film::TileSpec;

/// Why a set of tiles could not be merged.
#[derive(Debug, thiserror::Error)]
pub enum FarmError {
    /// No tile was given.
    #[error("no tiles to merge")]
    NoTiles,
    /// A tile could not be read from disk.
    // The cause is printed by the error chain (`error: {e:#}`), so not repeated here.
    #[error("{path}: cannot read the tile")]
    Read {
        /// The tile.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A tile is no OpenEXR file lumis can read, or not one lumis writes.
    #[error("{path}: {message}")]
    Format {
        /// The tile.
        path: PathBuf,
        /// What was found and what was expected.
        message: String,
    },
    /// A tile differs from the first tile in something that must be equal.
    #[error(
        "{path}: {what} differs from {first}'s ({detail}); the tiles come from different \
         renders, so they cannot be merged"
    )]
    Mismatch {
        /// The tile that differs.
        path: PathBuf,
        /// The first tile given, the reference.
        first: PathBuf,
        /// What differs (`the scene hash (lumis/sceneHash)`).
        what: String,
        /// The two values, or a summary.
        detail: String,
    },
    /// The same tile index was given twice.
    #[error("{second}: tile {spec} was given twice (also {first})")]
    Duplicate {
        /// The index.
        spec: TileSpec,
        /// The first file holding it.
        first: PathBuf,
        /// The second file holding it.
        second: PathBuf,
    },
    /// Tiles of the split are missing.
    #[error(
        "tile{} {} of {count} missing: every tile 0..{} must be given (re-run the missing \
         job{})",
        if missing.len() > 1 { "s" } else { "" },
        list(missing),
        count - 1,
        if missing.len() > 1 { "s" } else { "" }
    )]
    Missing {
        /// How many tiles the split has.
        count: u32,
        /// The indices not given.
        missing: Vec<u32>,
    },
    /// A tile was stopped before all its pixels were rendered (`lumis/partial`).
    #[error("{path}: tile {spec} is partial (its render was stopped early); render it again")]
    Partial {
        /// The tile.
        path: PathBuf,
        /// Its index.
        spec: TileSpec,
    },
}

/// `1, 3 and 4`, at most 20 of them.
fn list(indices: &[u32]) -> String {
    let shown: Vec<String> = indices.iter().take(20).map(u32::to_string).collect();
    let more = if indices.len() > 20 { ", ..." } else { "" };
    match shown.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}{more}", rest.join(", ")),
        _ => format!("{}{more}", shown.join("")),
    }
}
