//! Which pixels job `I` of `N` renders: a fixed split of the image into `N` horizontal strips.
//!
//! Strips, not a grid, because OpenEXR scanline files store whole rows: a strip is one
//! contiguous block of every channel, so the merge copies tiles without reordering. Their edges
//! fall on multiples of [`SPLIT_ROWS`] rows (the renderer's own bucket height) while there are
//! at least `N` bands of that height, so every job renders whole buckets; past that, on whole
//! rows. The split depends on nothing but `(I, N, width, height)`, so every job and the merge
//! compute it alike.

use std::fmt;
use std::str::FromStr;

use super::PixelWindow;

/// Rows per band of the split while the image has at least `N` such bands.
pub const SPLIT_ROWS: u32 = 16;

/// Tile `index` (0-based) of `count`: the `I/N` of `--tile I/N`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TileSpec {
    /// 0-based index, below `count` (Slurm's `SLURM_ARRAY_TASK_ID` with `--array=0-(N-1)`,
    /// Kubernetes' `JOB_COMPLETION_INDEX`).
    pub index: u32,
    /// How many tiles the image is cut into, at least 1.
    pub count: u32,
}

impl fmt::Display for TileSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for TileSpec {
    type Err = String;

    /// `I/N` with `0 <= I < N`.
    fn from_str(s: &str) -> Result<Self, String> {
        let expected = || format!("expected I/N with 0 <= I < N (0-based index), got {s:?}");
        let (i, n) = s.split_once('/').ok_or_else(expected)?;
        let index: u32 = i.trim().parse().map_err(|_| expected())?;
        let count: u32 = n.trim().parse().map_err(|_| expected())?;
        if count == 0 || index >= count {
            return Err(expected());
        }
        Ok(Self { index, count })
    }
}

impl TileSpec {
    /// The pixels of this tile in a `width x height` image; an error when the image has fewer
    /// rows than tiles (a tile would be empty).
    pub fn window(self, width: u32, height: u32) -> Result<PixelWindow, String> {
        if self.count == 0 || self.index >= self.count {
            return Err(format!("tile {self}: the index must be below the count"));
        }
        if self.count > height || width == 0 {
            return Err(format!(
                "tile {self}: a {width}x{height} image has only {height} rows to share \
                 among {} tiles; use at most {height} tiles",
                self.count
            ));
        }
        Ok(PixelWindow {
            x0: 0,
            x1: width,
            y0: row_start(self.index, self.count, height),
            y1: row_start(self.index + 1, self.count, height),
        })
    }

    /// Every tile of a split into `count`, in order.
    pub fn all(count: u32) -> impl Iterator<Item = TileSpec> {
        (0..count).map(move |index| TileSpec { index, count })
    }
}

/// The first row of tile `i` of `n` (`i = n` gives `height`): band edges spread as evenly as
/// integers allow, in u64 so that `i * bands` cannot overflow.
fn row_start(i: u32, n: u32, height: u32) -> u32 {
    let (i, n) = (u64::from(i), u64::from(n));
    let bands = u64::from(height.div_ceil(SPLIT_ROWS));
    let row = if n <= bands {
        (i * bands / n) * u64::from(SPLIT_ROWS)
    } else {
        i * u64::from(height) / n
    };
    row.min(u64::from(height)) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every split of every small image covers each row exactly once with non-empty strips.
    #[test]
    fn strips_cover_every_row_once_and_none_is_empty() {
        for height in 1..=70 {
            for count in 1..=height {
                let mut next = 0;
                for tile in TileSpec::all(count) {
                    let w = tile.window(5, height).unwrap();
                    assert_eq!((w.x0, w.x1, w.y0), (0, 5, next), "{tile} of {height}");
                    assert!(w.y1 > w.y0, "{tile} of {height} is empty");
                    next = w.y1;
                }
                assert_eq!(next, height);
            }
        }
    }

    #[test]
    fn edges_fall_on_buckets_while_there_are_enough() {
        // 1080 rows = 68 bands (the last one 8 rows): 4 tiles of 17 bands.
        let starts: Vec<u32> = TileSpec::all(4)
            .map(|t| t.window(1920, 1080).unwrap().y0)
            .collect();
        assert_eq!(starts, [0, 272, 544, 816]);
        // 40 rows = 3 bands; 7 tiles fall back to whole rows.
        let w = TileSpec { index: 1, count: 7 }.window(8, 40).unwrap();
        assert_eq!((w.y0, w.y1), (5, 11));
    }

    #[test]
    fn bad_specs_and_too_many_tiles_are_refused() {
        assert_eq!("2/7".parse(), Ok(TileSpec { index: 2, count: 7 }));
        for bad in ["7/7", "1/0", "-1/4", "1", "a/b", "1/4/5"] {
            assert!(
                bad.parse::<TileSpec>().unwrap_err().contains("I/N"),
                "{bad}"
            );
        }
        let err = TileSpec { index: 0, count: 9 }.window(4, 8).unwrap_err();
        assert!(err.contains("at most 8 tiles"), "{err}");
    }
}
