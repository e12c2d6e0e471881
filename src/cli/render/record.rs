//! The pixel flags of a render as given on the command line, for its EXR header
//! (`lumis/settings`), and back into arguments for `lumis render --from`.
//!
//! The flags are read from clap's matches, not from the parsed options, so that every flag
//! is recorded by the name the command line knows it by, with the value as typed, and so that
//! no flag added later can be forgotten here: only the ones in [`NOT_PIXEL_FLAGS`] are left
//! out.

use super::RenderArgs;
use clap::parser::ValueSource;
use clap::{ArgMatches, Args, Command};
use std::collections::BTreeMap;

/// Options that do not change the pixels (outputs, threads, reporting, the viewer), or that
/// the header records on their own (`lumis/seed`, `lumis/tile`, `lumis/frame`), or that are
/// the scene itself (recorded in `lumis/replay`).
const NOT_PIXEL_FLAGS: [&str; 13] = [
    "scene",
    "output",
    "png",
    "threads",
    "seed",
    "timing_metadata",
    "quiet",
    "stats",
    "stats_json",
    "display_server",
    "from",
    "tile",
    "frame",
];

/// `lumis render`'s arguments as a command of their own (what `--from` parses).
pub(super) fn command() -> Command {
    RenderArgs::augment_args(Command::new("lumis render").no_binary_name(true))
}

/// Options of the command that runs a replay that it keeps its own (not the image's).
const OWN_FLAGS: [&str; 7] = [
    "output",
    "png",
    "threads",
    "quiet",
    "stats",
    "stats_json",
    "display_server",
];

/// The pixel flags given on the command line in `matches`, by their name there (`--spp`,
/// `-D`), each with its values as typed (none for a switch).
pub(super) fn pixel_flags(matches: &ArgMatches) -> BTreeMap<String, Vec<String>> {
    given(matches, |id| !NOT_PIXEL_FLAGS.contains(&id))
}

/// The outputs, threads and reporting options given in `matches`, as arguments.
pub(super) fn own_args(matches: &ArgMatches) -> Vec<String> {
    flag_args(&given(matches, |id| OWN_FLAGS.contains(&id)))
}

/// The options given on the command line in `matches` whose id `keep` accepts.
fn given(matches: &ArgMatches, keep: impl Fn(&str) -> bool) -> BTreeMap<String, Vec<String>> {
    let mut flags = BTreeMap::new();
    for arg in command().get_arguments() {
        let id = arg.get_id().as_str();
        if !keep(id) || matches.value_source(id) != Some(ValueSource::CommandLine) {
            continue;
        }
        let name = match (arg.get_long(), arg.get_short()) {
            (Some(long), _) => format!("--{long}"),
            (None, Some(short)) => format!("-{short}"),
            (None, None) => continue,
        };
        let values = if arg.get_action().takes_values() {
            matches
                .try_get_raw(id)
                .ok()
                .flatten()
                .map(|raw| raw.map(|v| v.to_string_lossy().into_owned()).collect())
                .unwrap_or_default()
        } else {
            Vec::new()
        };
        flags.insert(name, values);
    }
    flags
}

/// `flags` as command-line arguments again (`--name=value`, so that a value starting with `-`
/// stays a value; `-D value` for a short-only option).
pub(super) fn flag_args(flags: &BTreeMap<String, Vec<String>>) -> Vec<String> {
    let mut args = Vec::new();
    for (name, values) in flags {
        if values.is_empty() {
            args.push(name.clone());
        }
        for v in values {
            if name.starts_with("--") {
                args.push(format!("{name}={v}"));
            } else {
                args.push(name.clone());
                args.push(v.clone());
            }
        }
    }
    args
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(args: &[&str]) -> ArgMatches {
        command().try_get_matches_from(args).unwrap()
    }

    #[test]
    fn flags_round_trip_whatever_their_order() {
        let a = pixel_flags(&parse(&[
            "s.toml",
            "--spp",
            "3",
            "-D",
            "render.width=9",
            "--exposure",
            "-1.5",
            "--float",
            "--aov",
            "albedo,uv",
            "-o",
            "x.exr",
            "--threads",
            "2",
            "--seed",
            "4",
        ]));
        let b = pixel_flags(&parse(&[
            "--float",
            "--aov=albedo",
            "--aov=uv",
            "--exposure=-1.5",
            "-D",
            "render.width=9",
            "--spp=3",
        ]));
        assert_eq!(a, b);
        assert_eq!(a["--spp"], ["3"]);
        assert_eq!(a["--float"], Vec::<String>::new());
        assert!(!a.contains_key("--threads") && !a.contains_key("--seed"));
        assert!(!a.contains_key("--output"));
        let again: Vec<String> = flag_args(&a);
        let refs: Vec<&str> = again.iter().map(String::as_str).collect();
        assert_eq!(pixel_flags(&parse(&refs)), a);
    }
}
