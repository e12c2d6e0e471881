//! `lumis render --frame F`: one frame of a TOML scene's `[animation]`, so that a frame
//! sequence renders as a job array, one task per frame (`tools/slurm/render_frames.sbatch`).
//!
//! The frame poses the scene when it loads (the `-D` overrides are applied first, so they can
//! change the keys); the outputs' last run of `#` becomes the zero-padded frame number, as in
//! Blender (`-o out/frame_####.exr --frame 7` writes `out/frame_0007.exr`), and the EXR header
//! records the frame (`lumis/frame`, `framesPerSecond`, `timeCode`). An animated scene
//! rendered without `--frame` is its frame 0, named and stamped as such; a still has no
//! frames, and `#` in its outputs stays as written.

use anyhow::Result;
use clap::Args;
use lumis_core::scene::Frame;
use lumis_io::output::{PlannedOutput, numbered_path};
use std::path::PathBuf;

/// `--frame`.
#[derive(Args, Debug, Default)]
pub struct FrameArgs {
    /// Render frame F (from 0) of the scene's [animation]; a run of # in -o and --png becomes
    /// F zero-padded to its length (frame_####.exr -> frame_0007.exr). Only TOML scenes with
    /// an [animation] table have frames; without --frame an animated scene renders frame 0.
    #[arg(long, value_name = "F")]
    frame: Option<u32>,
}

impl FrameArgs {
    /// The frame asked for.
    pub fn frame(&self) -> Option<u32> {
        self.frame
    }
}

/// The flags whose paths take the frame number: the images. (`--stats-json` keeps the name
/// it was given; a job array gives each task its own.)
const NUMBERED: [&str; 2] = ["-o", "--png"];

/// A run's outputs with the frame number in their names.
#[derive(Debug)]
pub struct NumberedOutputs {
    outputs: Vec<(String, PathBuf)>,
}

impl NumberedOutputs {
    /// `planned` with each image path numbered by `frame` (unchanged for a still).
    pub fn new(planned: &[PlannedOutput<'_>], frame: Option<Frame>) -> Result<Self> {
        let outputs = planned
            .iter()
            .map(|o| {
                let path = match frame {
                    Some(f) if NUMBERED.contains(&o.flag) => {
                        numbered_path(o.path, f.number()).map_err(anyhow::Error::msg)?
                    }
                    _ => o.path.to_path_buf(),
                };
                Ok((o.flag.to_owned(), path))
            })
            .collect::<Result<_>>()?;
        Ok(Self { outputs })
    }

    /// The outputs, as the rest of the run plans them.
    pub fn planned(&self) -> Vec<PlannedOutput<'_>> {
        self.outputs
            .iter()
            .map(|(flag, path)| PlannedOutput { flag, path })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lumis_core::scene::FrameRate;
    use std::path::Path;

    #[test]
    fn images_are_numbered_and_the_report_is_not() {
        let planned = [
            PlannedOutput {
                flag: "-o",
                path: Path::new("out/frame_####.exr"),
            },
            PlannedOutput {
                flag: "--png",
                path: Path::new("preview_##.png"),
            },
            PlannedOutput {
                flag: "--stats-json",
                path: Path::new("stats_####.json"),
            },
        ];
        let frame = Frame::new(7, 48, FrameRate::FILM).unwrap();
        let numbered = NumberedOutputs::new(&planned, Some(frame)).unwrap();
        let paths: Vec<&Path> = numbered.planned().iter().map(|o| o.path).collect();
        assert_eq!(
            paths,
            [
                Path::new("out/frame_0007.exr"),
                Path::new("preview_07.png"),
                Path::new("stats_####.json")
            ]
        );
        let still = NumberedOutputs::new(&planned, None).unwrap();
        assert_eq!(still.planned()[0].path, Path::new("out/frame_####.exr"));
        assert_eq!(still.planned()[1].flag, "--png");
    }
}
