//! The identity of a render for its EXR header (`lumis/sceneHash`, `lumis/seed`,
//! `lumis/settings`): what `lumis merge` compares to tell whether tiles belong together.
//!
//! Only what changes the pixels goes in: the output paths, `--threads`, `--quiet`, `--stats`,
//! `--timing-metadata` and `--tile` itself do not, so every tile of a render and the render
//! made in one go record the same identity.

use super::RenderArgs;
use anyhow::{Context, Result};
use lumis_core::scene::Settings;
use lumis_io::files::InputFile;
use lumis_io::output::{AovLayers, RenderIdentity};
use std::fmt::Write as _;

impl RenderArgs {
    /// The identity of this render of a scene read from `inputs`, with `settings` after every
    /// override and `exposure` the exposure it applies (`None`: automatic).
    pub(super) fn identity(
        &self,
        inputs: &[InputFile],
        settings: &Settings,
        exposure: Option<f32>,
    ) -> Result<RenderIdentity> {
        let scene_hash = lumis_io::farm::scene_hash(inputs, &self.load_options()?)
            .context("hashing the scene's files for the EXR header")?;
        Ok(RenderIdentity {
            scene_hash,
            seed: self.seed,
            settings: self.pixel_settings(settings, exposure),
        })
    }

    /// Everything besides the files that decides what is loaded (the `--env` flags among the
    /// defines they stand for).
    fn load_options(&self) -> Result<String> {
        let source = if self.scene.is_some() {
            "file"
        } else {
            "the built-in default scene"
        };
        // Only when given: renders without it keep the identity they always had.
        let flattened = if self.flatten_instances {
            "flatten instances: true\n"
        } else {
            ""
        };
        Ok(format!(
            "source: {source}\ndefines: {:?}\ngltf scene: {:?}\ncamera: {:?}\nauto camera: {}\nup: {:?}\n{flattened}",
            self.defines()?,
            self.gltf_scene,
            self.camera,
            self.auto_camera,
            self.up,
        ))
    }

    /// The settings that change the pixels, one `key: value` per line.
    fn pixel_settings(&self, settings: &Settings, exposure: Option<f32>) -> String {
        let mut s = String::new();
        let exposure = exposure.map_or("auto".to_string(), |ev| ev.to_string());
        let cryptomatte = self.passes.cryptomatte().ok().flatten();
        // Writing to a String cannot fail.
        // Every field of the settings (from Debug, so that a new field cannot be left out),
        // each on its own line, so that a merge refusing tiles names just the ones that differ.
        // Adaptive supersampling off is left out, so that renders without it keep the
        // identity they had before it existed.
        for field in top_level_fields(&format!("{settings:?}")) {
            if field != "adaptive: None" {
                let _ = writeln!(s, "{field}");
            }
        }
        let _ = writeln!(s, "effects: {:?}", self.effects);
        let _ = writeln!(s, "accel: {:?}", self.accel);
        let _ = writeln!(s, "exposure: {exposure}");
        let _ = writeln!(s, "z miss: {}", self.window.z_miss);
        let _ = writeln!(s, "float rgba: {}", self.float);
        // The layers asked for, in the text this line had before `id.instance`: that layer
        // follows the scene, which the scene hash covers, and tiles rendered before it keep
        // merging with tiles rendered after.
        let AovLayers {
            albedo,
            position,
            uv,
            samples,
            instance: _,
        } = self.passes.aov_layers(false);
        // `samples` only when asked for, so that the line of renders without it is unchanged.
        let samples = if samples { ", samples: true" } else { "" };
        let _ = writeln!(
            s,
            "aov: AovLayers {{ albedo: {albedo}, position: {position}, uv: {uv}{samples} }}"
        );
        let _ = writeln!(s, "passes: {:?}", self.passes.pass_request(true));
        let _ = writeln!(s, "cryptomatte levels: {cryptomatte:?}");
        let _ = writeln!(s, "layout: {:?}", self.passes.layout());
        let _ = write!(s, "transparent: {}", self.passes.transparent());
        s
    }
}

/// The `name: value` fields of a struct's one-line Debug text (`S { a: 1, b: V(1, 2) }`),
/// split at the commas outside any bracket; the whole text when it has no braces.
fn top_level_fields(debug: &str) -> Vec<String> {
    let (Some(open), Some(close)) = (debug.find('{'), debug.rfind('}')) else {
        return vec![debug.to_string()];
    };
    let mut fields = Vec::new();
    let (mut depth, mut field) = (0i32, String::new());
    for c in debug[open + 1..close].chars() {
        match c {
            '(' | '[' | '{' => depth += 1,
            ')' | ']' | '}' => depth -= 1,
            ',' if depth == 0 => {
                fields.push(field.trim().to_string());
                field.clear();
                continue;
            }
            _ => {}
        }
        field.push(c);
    }
    if !field.trim().is_empty() {
        fields.push(field.trim().to_string());
    }
    fields
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_split_outside_brackets_only() {
        let text = format!("{:?}", Settings::default());
        let fields = top_level_fields(&text);
        assert!(fields.iter().any(|f| f == "width: 640"), "{fields:?}");
        assert!(
            fields.iter().any(|f| f.starts_with("ambient: Vec3(")),
            "{fields:?}"
        );
        assert!(fields.iter().all(|f| f.contains(": ")), "{fields:?}");
        assert_eq!(top_level_fields("Inner(1, 2)"), ["Inner(1, 2)"]);
    }
}
