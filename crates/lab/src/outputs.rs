//! The files a benchmark writes (`--csv`, `--plot`), under the rules every lumis output follows
//! (`lumis_io::output`, docs/robustness.md "Outputs"). A benchmark runs for minutes, so its
//! outputs are checked before anything is measured: a FIFO, a device, a directory, a missing
//! directory or a link to one is refused at once (and an output that is a scene the run reads,
//! as soon as the scenes are loaded), not after the measuring. At the end the results go
//! through [`StagedOutputs`]: temporary files renamed into place together, a symlink to a
//! regular file written through.

use anyhow::Result;
use lumis_io::files::record_inputs;
use lumis_io::output::{PlannedOutput, StagedOutputs, prepare_outputs};
use std::path::Path;

/// A benchmark's result files, checked (see the module docs).
pub struct BenchOutputs<'a> {
    planned: Vec<PlannedOutput<'a>>,
}

impl<'a> BenchOutputs<'a> {
    /// The files of the options in `flags` that were given, checked before anything is read.
    pub fn prepare(flags: &[(&'a str, Option<&'a Path>)]) -> Result<Self> {
        let planned: Vec<PlannedOutput<'a>> = flags
            .iter()
            .filter_map(|&(flag, path)| path.map(|path| PlannedOutput { flag, path }))
            .collect();
        prepare_outputs(&planned, &[])?;
        Ok(Self { planned })
    }

    /// Runs `load`, noting every file it reads, and then checks the outputs again against
    /// those files, so that no result replaces a scene, mesh or texture of the run.
    pub fn load<T>(&self, load: impl FnOnce() -> Result<T>) -> Result<T> {
        let (loaded, inputs) = record_inputs(load);
        let loaded = loaded?;
        prepare_outputs(&self.planned, &inputs)?;
        Ok(loaded)
    }

    /// Writes `files` (each an output given to [`prepare`](Self::prepare) and its bytes):
    /// every one to a temporary file first, then all renamed into place, or none.
    pub fn write(&self, files: &[(&Path, &[u8])]) -> Result<()> {
        let mut staged = StagedOutputs::new();
        for (path, bytes) in files {
            debug_assert!(self.planned.iter().any(|p| p.path == *path));
            staged.stage_bytes(path, bytes)?;
        }
        staged.commit()?;
        Ok(())
    }
}
