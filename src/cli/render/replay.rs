//! `lumis render --from IMAGE.exr`: the render an image's header records, made again. The
//! header holds the pixel flags as given (`lumis/settings`), the scene path and a digest of
//! every file read (`lumis/replay`), the seed, tile and frame; replaying parses those as a
//! command line of their own, with this command's outputs, threads and reporting, and
//! renders it, so the image comes out byte for byte (images made with `--timing-metadata`
//! or cut short by Ctrl-C excepted).

use super::{RenderArgs, record};
use anyhow::{Context, Result, anyhow, bail};
use clap::{ArgMatches, FromArgMatches};
use lumis_io::output::{ATTR_RENDERER, ATTR_REPLAY, ATTR_SETTINGS, ExrFile, SOFTWARE};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

/// What `lumis/settings` holds that a replay reads.
#[derive(Deserialize)]
struct SettingsRecord {
    flags: BTreeMap<String, Vec<String>>,
}

/// `lumis/replay`.
#[derive(Deserialize)]
struct ReplayRecord {
    scene: Option<String>,
    inputs: BTreeMap<String, String>,
}

/// Renders again what `image` was rendered from; `args` and `matches` are this command's
/// (which may only add outputs, threads, reporting and a viewer).
pub(super) fn run(args: &RenderArgs, matches: &ArgMatches, image: &Path) -> Result<()> {
    let given = record::pixel_flags(matches);
    if !given.is_empty() {
        let names: Vec<&str> = given.keys().map(String::as_str).collect();
        bail!(
            "--from {}: the image's own flags are replayed; {} cannot be added (only outputs, \
             --threads, --quiet, --stats, --stats-json and --display-server)",
            image.display(),
            names.join(", ")
        );
    }
    let argv = replay_args(image)?;
    let mut argv: Vec<String> = argv;
    argv.extend(record::own_args(matches));
    let m = record::command()
        .try_get_matches_from(&argv)
        .with_context(|| {
            format!(
                "--from {}: its recorded flags no longer parse",
                image.display()
            )
        })?;
    let replayed = RenderArgs::from_arg_matches(&m).map_err(|e| anyhow!(e.to_string()))?;
    if !args.quiet {
        eprintln!("replaying: lumis render {}", argv.join(" "));
    }
    super::run(&replayed, &m)
}

/// The command line `image` records, checked against the files it names; the errors name the
/// image and say why it cannot be replayed.
fn replay_args(image: &Path) -> Result<Vec<String>> {
    let file = ExrFile::open(image)?;
    let header = file.header();
    let at = |name: &str| header.attributes.get(name).map(ToString::to_string);
    let shown = image.display();
    let Some(settings) = at(ATTR_SETTINGS) else {
        bail!("--from {shown}: no {ATTR_SETTINGS}: not an image lumis render wrote");
    };
    let settings: SettingsRecord = serde_json::from_str(&settings).map_err(|_| {
        anyhow!(
            "--from {shown}: its {ATTR_SETTINGS} is the text record of an older lumis, which \
             cannot be replayed (only images with the JSON record can)"
        )
    })?;
    let made_by = at(ATTR_RENDERER).unwrap_or_else(|| "an unknown version".into());
    if made_by != SOFTWARE {
        bail!(
            "--from {shown}: made by {made_by}, this is {SOFTWARE}: another version may give \
             other pixels, so it is not replayed"
        );
    }
    let replay: ReplayRecord = at(ATTR_REPLAY)
        .and_then(|r| serde_json::from_str(&r).ok())
        .ok_or_else(|| anyhow!("--from {shown}: no readable {ATTR_REPLAY} record"))?;
    for (path, digest) in &replay.inputs {
        // A header is the file's word only: a device or FIFO named there is never read.
        if std::fs::metadata(path).is_ok_and(|m| !m.is_file()) {
            bail!("--from {shown}: its input {path} is not a regular file");
        }
        match lumis_io::farm::file_digest(Path::new(path)) {
            Ok(now) if now == *digest => {}
            Ok(_) => bail!("--from {shown}: its input {path} has changed since the image was made"),
            Err(e) => bail!("--from {shown}: its input {path} cannot be read ({e})"),
        }
    }
    let meta = &header.meta;
    let seed = meta
        .identity
        .as_ref()
        .map(|id| id.seed)
        .ok_or_else(|| anyhow!("--from {shown}: no seed recorded"))?;
    let mut argv: Vec<String> = replay.scene.into_iter().collect();
    argv.extend(record::flag_args(&settings.flags));
    argv.push(format!("--seed={seed}"));
    if let Some(tile) = &meta.tile {
        argv.push(format!("--tile={}", tile.spec));
    }
    if let Some(frame) = meta.frame {
        argv.push(format!("--frame={}", frame.number()));
    }
    Ok(argv)
}
