//! How the EXR's channels are named: lumis's own short names, or Blender's multilayer
//! convention (`ViewLayer.Combined.R`), which compositors that read Blender renders (Blender,
//! Nuke's multi-layer readers, Resolve) sort into named layers.
//!
//! | lumis            | blender                          |
//! |------------------|----------------------------------|
//! | `R` `G` `B` `A`  | `ViewLayer.Combined.R/G/B/A`     |
//! | `Z`              | `ViewLayer.Depth.Z`              |
//! | `N.X/Y/Z`        | `ViewLayer.Normal.X/Y/Z`         |
//! | `id.object`      | `ViewLayer.IndexOB.X`            |
//! | `id.prim`        | `ViewLayer.IndexPrim.X` (lumis's own; Blender has no such pass) |
//! | `id.instance`    | `ViewLayer.IndexInstance.X` (lumis's own, named like `IndexOB`) |
//! | `albedo.R/G/B`   | `ViewLayer.DiffCol.R/G/B`        |
//! | `P.X/Y/Z`        | `ViewLayer.Position.X/Y/Z`       |
//! | `uv.U/V`         | `ViewLayer.UV.U/V`, plus `ViewLayer.UV.A` (1 on hits, 0 on misses) |
//! | `samples`        | `ViewLayer.Debug Sample Count.X` (Cycles' pass of the samples taken) |
//! | `CryptoObject00.R` | `ViewLayer.CryptoObject00.R` (type name `ViewLayer.CryptoObject`) |
//! | `diffuse.R/G/B`  | `ViewLayer.DiffDir.R/G/B`        |
//! | `specular.*`     | `ViewLayer.GlossDir.*`           |
//! | `reflection.*`   | `ViewLayer.GlossInd.*`           |
//! | `refraction.*`   | `ViewLayer.TransInd.*`           |
//! | `emission.*`     | `ViewLayer.Emit.*`               |
//! | `background.*`   | `ViewLayer.Env.*`                |
//! | `ambient.*`      | `ViewLayer.Ambient.*` (lumis's own; Blender has no such pass) |
//! | `light.key.*`    | `ViewLayer.Combined_key.*` (Blender's light-group passes) |
//! | `shadow.*`       | `ViewLayer.Shadow Catcher.*`     |
//!
//! The pass names are Blender's own (`RE_PASSNAME_*`: `Combined`, `Depth`, `Normal`,
//! `IndexOB`, `DiffCol`, `Position`, `UV`) with the channel letters Blender gives each pass
//! (`RGBA`, `Z`, `XYZ`, `X`, `RGB`, `XYZ`, `UVA`), joined with dots after the view layer.

/// The channel naming convention of the EXR.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ChannelLayout {
    /// lumis's names (`R`, `Z`, `N.X`, `albedo.R`, `CryptoObject00.R`, ...).
    #[default]
    Lumis,
    /// Blender's multilayer names (`ViewLayer.Combined.R`, `ViewLayer.Depth.Z`, ...).
    Blender,
}

/// The view layer every Blender name is prefixed with (Blender's default view layer).
const VIEW_LAYER: &str = "ViewLayer";

impl ChannelLayout {
    /// Every layout, for a reader to tell which one a file has.
    pub const ALL: [ChannelLayout; 2] = [Self::Lumis, Self::Blender];

    /// The name used on the command line (`--layout`) and in Python (`layout=`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Lumis => "lumis",
            Self::Blender => "blender",
        }
    }

    /// The names of the R, G, B, A channels in this layout: what tells the layouts apart in
    /// a file, and what a farm tile records in `lumis/tileBeauty`.
    pub fn beauty(self) -> [String; 4] {
        ["R", "G", "B", "A"].map(|c| self.channel(c))
    }

    /// The name channel `name` (given in the lumis layout) has in this layout.
    pub fn channel(self, name: &str) -> String {
        match self {
            Self::Lumis => name.to_string(),
            Self::Blender => {
                let renamed = match name {
                    "R" | "G" | "B" | "A" => format!("Combined.{name}"),
                    "Z" => "Depth.Z".to_string(),
                    "id.object" => "IndexOB.X".to_string(),
                    "id.prim" => "IndexPrim.X".to_string(),
                    "id.instance" => "IndexInstance.X".to_string(),
                    "samples" => "Debug Sample Count.X".to_string(),
                    // A light's name has no dots (`Scene::light_names`): the channel is last.
                    _ if name.starts_with("light.") => match name[6..].rsplit_once('.') {
                        Some((light, c)) => format!("Combined_{light}.{c}"),
                        None => name.to_string(),
                    },
                    _ => match name.split_once('.') {
                        Some((layer, c)) => format!("{}.{c}", blender_pass(layer)),
                        None => name.to_string(),
                    },
                };
                format!("{VIEW_LAYER}.{renamed}")
            }
        }
    }

    /// Whether the UV pass has a third channel `A` besides `U` and `V`. Blender's UV pass has
    /// three channels, `UVA` (its manual: the third holds a constant 1 and no information),
    /// and files meant to pass for Blender's should have the passes Blender's compositor
    /// expects; lumis writes A = 1 where the centre ray hit and 0 where nothing was there.
    /// lumis's own layout keeps just the two coordinates.
    pub fn uv_has_alpha(self) -> bool {
        self == Self::Blender
    }

    /// The Cryptomatte type name of `name` (`CryptoObject`) in this layout: the prefix of its
    /// channels and the `name` its metadata records.
    pub fn crypto_type(self, name: &str) -> String {
        match self {
            Self::Lumis => name.to_string(),
            Self::Blender => format!("{VIEW_LAYER}.{name}"),
        }
    }

    /// The lumis type name (`CryptoObject`) of the recorded Cryptomatte name `recorded`:
    /// [`Self::crypto_type`] undone; `None` when this layout makes no such name.
    pub fn crypto_name(self, recorded: &str) -> Option<&str> {
        let name = match self {
            Self::Lumis => recorded,
            Self::Blender => recorded.strip_prefix(VIEW_LAYER)?.strip_prefix('.')?,
        };
        (self.crypto_type(name) == recorded).then_some(name)
    }
}

impl std::str::FromStr for ChannelLayout {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|l| l.name() == s)
            .ok_or_else(|| format!("unknown layout {s:?}; expected lumis or blender"))
    }
}

/// Blender's pass name for a lumis layer name.
fn blender_pass(layer: &str) -> &str {
    match layer {
        "N" => "Normal",
        "albedo" => "DiffCol",
        "P" => "Position",
        "uv" => "UV",
        // The light-path passes: Blender's names where it has the pass (Cycles puts
        // everything seen through the first glossy or transmission bounce in its indirect
        // pass, as lumis splits at the first hit).
        "diffuse" => "DiffDir",
        "specular" => "GlossDir",
        "reflection" => "GlossInd",
        "refraction" => "TransInd",
        "emission" => "Emit",
        "background" => "Env",
        "ambient" => "Ambient",
        "shadow" => "Shadow Catcher",
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blender_names() {
        let b = ChannelLayout::Blender;
        for (lumis, blender) in [
            ("R", "ViewLayer.Combined.R"),
            ("A", "ViewLayer.Combined.A"),
            ("Z", "ViewLayer.Depth.Z"),
            ("N.Y", "ViewLayer.Normal.Y"),
            ("id.object", "ViewLayer.IndexOB.X"),
            ("id.instance", "ViewLayer.IndexInstance.X"),
            ("albedo.G", "ViewLayer.DiffCol.G"),
            ("P.Z", "ViewLayer.Position.Z"),
            ("uv.V", "ViewLayer.UV.V"),
            ("uv.A", "ViewLayer.UV.A"),
            ("samples", "ViewLayer.Debug Sample Count.X"),
            ("CryptoObject01.B", "ViewLayer.CryptoObject01.B"),
            ("diffuse.R", "ViewLayer.DiffDir.R"),
            ("specular.G", "ViewLayer.GlossDir.G"),
            ("reflection.B", "ViewLayer.GlossInd.B"),
            ("refraction.R", "ViewLayer.TransInd.R"),
            ("emission.R", "ViewLayer.Emit.R"),
            ("background.G", "ViewLayer.Env.G"),
            ("ambient.B", "ViewLayer.Ambient.B"),
            ("light.key_2.R", "ViewLayer.Combined_key_2.R"),
            ("shadow.R", "ViewLayer.Shadow Catcher.R"),
        ] {
            assert_eq!(b.channel(lumis), blender);
            assert_eq!(ChannelLayout::Lumis.channel(lumis), lumis);
        }
        assert_eq!(b.crypto_type("CryptoMaterial"), "ViewLayer.CryptoMaterial");
        assert_eq!(
            b.crypto_name("ViewLayer.CryptoMaterial"),
            Some("CryptoMaterial")
        );
        assert_eq!(b.crypto_name("CryptoMaterial"), None);
        assert_eq!(
            ChannelLayout::Lumis.crypto_name("CryptoObject"),
            Some("CryptoObject")
        );
        assert!(b.uv_has_alpha() && !ChannelLayout::Lumis.uv_has_alpha());
    }
}
