//! The provenance of a render from a scene file, written into its EXR as `lumis render` writes
//! it (`lumis/sceneHash`, `lumis/seed`, `lumis/settings`, `lumis/replay`): the keyword
//! arguments become the command-line flags that ask for the same render, so that `lumis
//! render --from` replays Python's files and a merge compares them with the command's.

use std::collections::BTreeMap;

use lumis_core::accel::AccelKind;
use lumis_core::film::Tonemap;
use lumis_core::scene::{Settings, UpAxis};
use lumis_io::formats::Override;
use lumis_io::output::{ChannelLayout, RenderIdentity};
use lumis_io::request::settings_record;
use pyo3::PyResult;
use serde_json::json;

use crate::errors::SceneError;
use crate::render::Request;
use crate::source::FileSource;

/// The flags of `lumis render` that ask for what `file` was loaded with and `request` renders,
/// by their command-line names, values as the command line spells them; defaults left out,
/// as a command line that does not give them.
fn flags(file: &FileSource, request: &Request) -> BTreeMap<String, Vec<String>> {
    let mut f: BTreeMap<String, Vec<String>> = BTreeMap::new();
    let mut put = |name: &str, values: Vec<String>| {
        f.insert(name.to_string(), values);
    };
    let s = &request.settings;
    let number = |v: Option<u32>| v.map(|v| vec![v.to_string()]);
    for (name, v) in [
        ("--width", number(s.width)),
        ("--height", number(s.height)),
        ("--spp", number(s.spp)),
        ("--max-depth", number(s.max_depth)),
        (
            "--precision",
            s.precision.map(|p| vec![p.name().to_string()]),
        ),
        ("--display", s.display.map(|d| vec![d.name().to_string()])),
        (
            "--exposure",
            request.exposure.map(|ev| vec![ev.to_string()]),
        ),
    ] {
        if let Some(v) = v {
            put(name, v);
        }
    }
    if !request.aovs.is_empty() {
        put(
            "--aov",
            request.aovs.iter().map(|a| a.name().to_string()).collect(),
        );
    }
    if request.accel != AccelKind::Sah {
        put("--accel", vec![request.accel.name().to_string()]);
    }
    if request.layout != ChannelLayout::Lumis {
        put("--layout", vec![request.layout.name().to_string()]);
    }
    if request.tonemap != Tonemap::None {
        put("--tonemap", vec![request.tonemap.name().to_string()]);
    }
    for (name, on) in [
        ("--transparent", request.transparent),
        ("--float", request.float_rgba),
        ("--auto-camera", file.options.auto_camera),
        ("--flatten-instances", file.options.flatten_instances),
    ] {
        if on {
            put(name, Vec::new());
        }
    }
    let o = &file.options;
    if let Some(n) = o.scene {
        put("--gltf-scene", vec![n.to_string()]);
    }
    if let Some(n) = o.camera {
        put("--camera", vec![n.to_string()]);
    }
    if o.up != UpAxis::default() {
        put("--up", vec![o.up.name().to_string()]);
    }
    if !file.defines.is_empty() {
        put("-D", file.defines.clone());
    }
    f
}

/// The identity `lumis render` would record for this render of `file` with `settings` (after
/// the request's overrides).
pub fn identity(
    file: &FileSource,
    request: &Request,
    settings: &Settings,
) -> PyResult<RenderIdentity> {
    let defines = file
        .defines
        .iter()
        .map(|d| d.parse::<Override>())
        .collect::<Result<Vec<_>, _>>()
        .map_err(SceneError::new_err)?;
    let load = lumis_io::farm::load_options_text(true, &defines, &file.options);
    let scene_hash =
        lumis_io::farm::scene_hash_of(file.digests.iter().map(|(_, d)| d.clone()).collect(), &load);
    let record = json!({
        "flags": flags(file, request),
        "render": settings_record(settings),
    });
    let inputs: BTreeMap<String, String> = file
        .digests
        .iter()
        .map(|(p, d)| (p.to_string_lossy().into_owned(), d.clone()))
        .collect();
    let replay = json!({
        "scene": file.given.to_string_lossy(),
        "inputs": inputs,
    });
    Ok(RenderIdentity {
        scene_hash,
        seed: request.seed,
        settings: record.to_string(),
        replay: Some(replay.to_string()),
    })
}
