//! Running one case: its directory, the binary under a timeout, and the verdict.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use exr::prelude::{FlatSamples, ReadChannels, ReadLayers, read};

use super::Case;

/// Longer than any clean run takes (they take milliseconds), short enough for a hang to cost
/// little.
const TIMEOUT: Duration = Duration::from_secs(10);
/// What `out.exr` holds before the run: a failed run must leave it so.
const SENTINEL: &[u8] = b"an existing output that a failed run must not change";

/// The verdict on one run.
pub enum Outcome {
    CleanError,
    Accepted,
    /// Neither; `item` is the issue-14 item whose branch fixes this class, when it is one.
    Bad {
        item: Option<u32>,
        why: String,
    },
}

/// One case, set up in its own directory.
pub struct Run<'a> {
    case: &'a Case,
    dir: PathBuf,
}

impl<'a> Run<'a> {
    pub fn new(case: &'a Case, dir: &Path) -> Self {
        std::fs::create_dir_all(dir).unwrap();
        for (name, bytes) in &case.files {
            std::fs::write(dir.join(name), bytes).unwrap();
        }
        if case.fifo {
            let ok = Command::new("mkfifo")
                .arg(dir.join(case.target))
                .status()
                .is_ok_and(|s| s.success());
            assert!(ok, "mkfifo failed");
        }
        std::fs::write(dir.join("out.exr"), SENTINEL).unwrap();
        Self {
            case,
            dir: dir.to_path_buf(),
        }
    }

    /// Runs the binary and judges the result.
    pub fn check(&self) -> Outcome {
        let (status, stderr) = match self.run() {
            Some(r) => r,
            None => {
                return Outcome::Bad {
                    item: self.case.fifo.then_some(3),
                    why: format!("no exit within {TIMEOUT:?}"),
                };
            }
        };
        let item = self.item(status, &stderr);
        let bad = |why: String| Outcome::Bad {
            item,
            why: format!("{why}; stderr: {}", stderr.trim()),
        };
        if stderr.contains("panicked") {
            return bad("a panic message".into());
        }
        match status {
            Some(0) => match self.check_outputs() {
                Ok(()) => Outcome::Accepted,
                Err(why) => bad(why),
            },
            Some(code) if code != 101 => {
                if !self.names_the_file(&stderr) {
                    return bad(format!(
                        "exit {code}, but the message does not name the file"
                    ));
                }
                match self.check_untouched() {
                    Ok(()) => Outcome::CleanError,
                    Err(why) => bad(why),
                }
            }
            other => bad(format!("exit status {other:?} (a panic or a signal)")),
        }
    }

    /// Exit code (`None`: killed by a signal) and stderr, or `None` on timeout.
    fn run(&self) -> Option<(Option<i32>, String)> {
        crate::common::cli::run_limited(&self.dir, &self.case.args, TIMEOUT)
            .map(|r| (r.status.code(), r.stderr))
    }

    /// The issue item whose branch owns a failure like this one, if any.
    fn item(&self, status: Option<i32>, stderr: &str) -> Option<u32> {
        let t = self.case.target;
        let dependency_panic = stderr.contains("panicked")
            || stderr.contains("the OBJ parser")
            || stderr.contains("the glTF reader");
        if self.case.fifo {
            Some(3)
        } else if dependency_panic
            && matches!(t, "model.mtl" | "model.obj" | "cube.gltf" | "cube.glb")
        {
            Some(1)
        } else if (status.is_none() || stderr.contains("memory allocation"))
            && matches!(t, "cube.gltf" | "cube.glb" | "cube.bin" | "rays.npy")
        {
            Some(2)
        } else {
            None
        }
    }

    /// The message names the damaged file, or for a file only ever read through another
    /// (texture, buffer) that one.
    fn names_the_file(&self, stderr: &str) -> bool {
        let via: &[&str] = match self.case.target {
            "tex.png" => &["model.mtl"],
            "cube.bin" => &["cube.gltf"],
            _ => &[],
        };
        std::iter::once(&self.case.target)
            .chain(via)
            .any(|name| stderr.contains(name))
    }

    /// A failed run wrote nothing: no new output, the existing one unchanged.
    fn check_untouched(&self) -> Result<(), String> {
        for name in ["out.png", "hits.npy"] {
            if self.dir.join(name).exists() {
                return Err(format!("failed, but left {name}"));
            }
        }
        if std::fs::read(self.dir.join("out.exr")).ok().as_deref() != Some(SENTINEL) {
            return Err("failed, but changed the existing out.exr".into());
        }
        Ok(())
    }

    /// An accepted render wrote both images, and the EXR's colour and normals are finite.
    fn check_outputs(&self) -> Result<(), String> {
        match self.case.args[0].as_str() {
            "render" => {
                if !self.dir.join("out.png").exists() {
                    return Err("exit 0 without out.png".into());
                }
                finite_exr(&self.dir.join("out.exr"))
            }
            "hits" if !self.dir.join("hits.npy").exists() => Err("exit 0 without hits.npy".into()),
            _ => Ok(()),
        }
    }
}

/// Every `R`, `G`, `B`, `A` and `N.*` sample of the EXR at `path` is finite.
pub fn finite_exr(path: &Path) -> Result<(), String> {
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| format!("exit 0, but out.exr does not read back: {e}"))?;
    let mut checked = 0;
    for c in &image.layer_data.channel_data.list {
        let name = c.name.to_string();
        if !matches!(name.as_str(), "R" | "G" | "B" | "A") && !name.starts_with("N.") {
            continue;
        }
        checked += 1;
        let values: Vec<f32> = match &c.sample_data {
            FlatSamples::F16(v) => v.iter().map(|h| h.to_f32()).collect(),
            FlatSamples::F32(v) => v.clone(),
            FlatSamples::U32(v) => v.iter().map(|&u| u as f32).collect(),
        };
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            let bad = values.iter().filter(|v| !v.is_finite()).count();
            return Err(format!(
                "exit 0, but channel {name} holds {bad} non-finite samples (first at {i}: {})",
                values[i]
            ));
        }
    }
    if checked != 7 {
        return Err(format!(
            "out.exr has {checked} of the 7 R, G, B, A, N.* channels"
        ));
    }
    Ok(())
}
