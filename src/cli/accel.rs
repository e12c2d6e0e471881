//! The accelerator flags shared by `render` and `hits`, validated in one place.

use super::values::{AccelArg, TraversalArg};
use anyhow::{Result, bail};
use clap::Args;
use lumis_core::accel::{
    AccelKind, BuildOptions, BuildQuality, PAPER_SEGMENT_MAX, SegmentParams, Traversal,
};
use lumis_core::scene::{Scene, World};

/// `--accel`, `--traversal`, `--segment-init`, `--segment-max`, `--leaf-size`, `--build`.
#[derive(Args, Debug)]
pub struct AccelArgs {
    /// Acceleration structure.
    #[arg(long, value_enum, default_value_t = AccelArg::Sah)]
    accel: AccelArg,
    /// How the hierarchy is walked: front-to-back, the paper's scale-lights segments, or the
    /// paper's exhaustive recursion.
    #[arg(long, value_enum, default_value_t = TraversalArg::Ordered)]
    traversal: TraversalArg,
    /// First segment length of the segments traversal (world units).
    #[arg(long, default_value_t = 2.0)]
    segment_init: f32,
    /// Segments double up to this length, then one unbounded pass follows.
    #[arg(long, default_value_t = PAPER_SEGMENT_MAX)]
    segment_max: f32,
    /// Largest leaf of the hierarchies (default: 4 for sah, 20 for bsp and bsmp, as in the paper).
    #[arg(long)]
    leaf_size: Option<usize>,
    /// How the sah hierarchy is built: full (binned and swept SAH over all primitives) or fast
    /// (SAH over Morton-order clusters, the full builder inside each: BENCHMARKS.md, "Build").
    #[arg(long, value_enum, default_value_t = BuildArg::Full)]
    build: BuildArg,
}

/// `--build`.
#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub enum BuildArg {
    Full,
    Fast,
}

/// A checked accelerator choice, ready to build.
pub struct AccelChoice {
    kind: AccelKind,
    options: BuildOptions,
    traversal: Traversal,
}

impl AccelArgs {
    /// The choice, or an error naming the bad flag (checked before any work is done).
    pub fn validated(&self) -> Result<AccelChoice> {
        let kind = AccelKind::from(self.accel);
        let options = BuildOptions {
            max_leaf_size: self.leaf_size.unwrap_or(kind.default_leaf_size()),
            quality: match self.build {
                BuildArg::Full => BuildQuality::Full,
                BuildArg::Fast => BuildQuality::Fast,
            },
        };
        if options.max_leaf_size == 0 {
            bail!("--leaf-size must be at least 1");
        }
        let (init, max) = (self.segment_init, self.segment_max);
        let traversal = match self.traversal {
            TraversalArg::Ordered => Traversal::Ordered,
            TraversalArg::Exhaustive => Traversal::Exhaustive,
            TraversalArg::Segments if init > 0.0 && init.is_finite() && max.is_finite() => {
                Traversal::Segments(SegmentParams { init, max })
            }
            TraversalArg::Segments => {
                bail!("--segment-init must be positive and both segment lengths finite")
            }
        };
        Ok(AccelChoice {
            kind,
            options,
            traversal,
        })
    }
}

impl AccelChoice {
    /// Builds the accelerator over `scene`'s primitives.
    pub fn build(&self, scene: Scene) -> World {
        World::build(scene, self.kind, &self.options).with_traversal(self.traversal)
    }
}
