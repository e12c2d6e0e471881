//! The identity of a render for its EXR header (`lumis/sceneHash`, `lumis/seed`,
//! `lumis/settings`): what `lumis merge` compares to tell whether tiles belong together, and
//! `lumis/replay`, the scene path and the files' digests, which `--from` needs besides.
//!
//! Only what changes the pixels goes into the settings: the output paths, `--threads`,
//! `--quiet`, `--stats`, `--timing-metadata` and `--tile` itself do not, so every tile of a
//! render and the render made in one go record the same identity.

use super::RenderArgs;
use anyhow::{Context, Result};
use clap::ArgMatches;
use lumis_core::scene::{Settings, UpAxis};
use lumis_io::files::InputFile;
use lumis_io::output::RenderIdentity;
use lumis_io::request::settings_record;
use serde_json::json;
use std::collections::BTreeMap;

impl RenderArgs {
    /// The identity of this render of a scene read from `inputs`, with `settings` after every
    /// override, its flags as given in `matches`.
    pub(super) fn identity(
        &self,
        inputs: &[InputFile],
        settings: &Settings,
        matches: &ArgMatches,
    ) -> Result<RenderIdentity> {
        let digests = lumis_io::farm::file_digests(inputs)
            .context("hashing the scene's files for the EXR header")?;
        let scene_hash = lumis_io::farm::scene_hash_of(
            digests.iter().map(|(_, d)| d.clone()).collect(),
            &self.load_options()?,
        );
        let settings = json!({
            "flags": super::record::pixel_flags(matches),
            "render": settings_record(settings),
        });
        let inputs: BTreeMap<String, String> = digests
            .into_iter()
            .map(|(path, digest)| (path.to_string_lossy().into_owned(), digest))
            .collect();
        let replay = json!({
            "scene": self.scene.as_ref().map(|p| p.to_string_lossy().into_owned()),
            "inputs": inputs,
        });
        Ok(RenderIdentity {
            scene_hash,
            seed: self.seed,
            settings: settings.to_string(),
            replay: Some(replay.to_string()),
        })
    }

    /// Everything besides the files that decides what is loaded (the `--env` flags among the
    /// defines they stand for), as Python's renders write it too.
    fn load_options(&self) -> Result<String> {
        let options = lumis_io::formats::LoadOptions {
            scene: self.gltf_scene,
            camera: self.camera,
            up: self.up.map(UpAxis::from).unwrap_or_default(),
            auto_camera: self.auto_camera,
            frame: None,
            flatten_instances: self.flatten_instances,
        };
        let defines = self.defines()?;
        Ok(lumis_io::farm::load_options_text(
            self.scene.is_some(),
            &defines,
            &options,
        ))
    }
}
