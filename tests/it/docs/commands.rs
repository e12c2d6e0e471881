//! The README's command lines: every flag is one the command's `--help` lists, and every
//! command runs as written (in a copy of the checkout's layout, the paper's scenes beside it);
//! docs/cli-reference.md is the binary's `--help`.

use super::repo;
use crate::common::cli::{assert_ok, binary};
use std::path::Path;
use std::process::Command;

/// The `lumis` command lines of the ```sh blocks of `text`: the words after `lumis` or
/// `cargo run --release --`.
fn command_lines(text: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let mut in_sh = false;
    for line in text.lines() {
        if line.starts_with("```") {
            in_sh = line == "```sh";
            continue;
        }
        if !in_sh {
            continue;
        }
        let line = line.split(" #").next().unwrap().trim();
        let words: Vec<&str> = line.split_whitespace().collect();
        let args = match words.as_slice() {
            ["cargo", "run", "--release", "--", rest @ ..] => rest,
            ["lumis", rest @ ..] => rest,
            _ => continue,
        };
        // Single quotes only group, as the shell's do (the examples quote no spaces).
        out.push(args.iter().map(|s| s.replace('\'', "")).collect());
    }
    out
}

const SUBCOMMANDS: [&str; 4] = ["render", "info", "hits", "merge"];

fn help(sub: &str) -> String {
    let mut cmd = Command::new(binary());
    if !sub.is_empty() {
        cmd.arg(sub);
    }
    let out = cmd.arg("--help").output().unwrap();
    assert_ok(&out);
    String::from_utf8(out.stdout).unwrap()
}

fn readme() -> String {
    std::fs::read_to_string(repo().join("README.md")).unwrap()
}

/// Panics unless every flag of command line `args` (a synopsis's `[--a X | --b]` included) is
/// one `--help` of its command lists.
fn assert_flags_known(args: &[String], origin: &str) {
    let sub = args
        .first()
        .filter(|a| SUBCOMMANDS.contains(&a.as_str()))
        .map_or("render", String::as_str);
    let help = help(sub);
    let words = args
        .iter()
        .flat_map(|a| a.split('|'))
        .map(|a| a.trim_matches(|c| c == '[' || c == ']'));
    for flag in words.filter(|a| a.starts_with('-') && a.len() > 1) {
        let flag = flag.split('=').next().unwrap();
        let known = [" ", ",", "\n", "="]
            .iter()
            .any(|end| help.contains(&format!("{flag}{end}")));
        assert!(
            known,
            "{origin}: `lumis {sub} --help` has no {flag} ({args:?})"
        );
    }
}

/// A synopsis rather than a command: placeholders, alternatives or optional parts.
fn is_synopsis(args: &[String]) -> bool {
    args.iter().any(|a| {
        a.contains(['[', ']', '|'])
            || a.contains("...")
            || a.chars().all(|c| c.is_ascii_uppercase())
    })
}

#[test]
fn the_readmes_flags_are_the_commands() {
    let lines = command_lines(&readme());
    assert!(lines.len() >= 2, "{lines:?}");
    for args in lines {
        assert_flags_known(&args, "README.md");
    }
}

#[test]
fn the_docs_command_lines_parse_and_run() {
    let (_root, checkout) = checkout_copy();
    let mut ran = 0;
    let docs = super::documents();
    for doc in docs.iter().filter(|d| d.starts_with(repo().join("docs"))) {
        let text = std::fs::read_to_string(doc).unwrap();
        let name = doc.file_name().unwrap().to_string_lossy().into_owned();
        for args in command_lines(&text) {
            assert_flags_known(&args, &name);
            if !is_synopsis(&args) && run_if_possible(&checkout, &args) {
                ran += 1;
            }
        }
    }
    assert!(ran >= 5, "only {ran} docs commands ran");
}

/// A copy of the checkout's layout in a temporary folder: the repository's asset folders, and
/// the paper's scenes beside it when this checkout has them. Returns the folder and the
/// checkout in it.
fn checkout_copy() -> (tempfile::TempDir, std::path::PathBuf) {
    let root = tempfile::tempdir().unwrap();
    let checkout = root.path().join("lumis");
    std::fs::create_dir(&checkout).unwrap();
    for dir in ["assets", "scenes"] {
        std::os::unix::fs::symlink(repo().join(dir), checkout.join(dir)).unwrap();
    }
    let shared = repo().join("../shared");
    if shared.exists() {
        std::os::unix::fs::symlink(&shared, root.path().join("shared")).unwrap();
    }
    (root, checkout)
}

/// Runs `lumis ARGS` in `checkout` and checks it succeeded and wrote its `-o` outputs; false
/// (not run) when it needs the paper's scenes and they are not there.
fn run_if_possible(checkout: &Path, args: &[String]) -> bool {
    if args.iter().any(|a| a.contains("../shared")) && !checkout.join("../shared").exists() {
        eprintln!("skipped (no ../shared): lumis {}", args.join(" "));
        return false;
    }
    let out = Command::new(binary())
        .args(args)
        .current_dir(checkout)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "lumis {}: exit {:?}\n{}",
        args.join(" "),
        out.status.code(),
        String::from_utf8_lossy(&out.stderr)
    );
    for o in args.windows(2).filter(|w| w[0] == "-o").map(|w| &w[1]) {
        let len = std::fs::metadata(checkout.join(o)).map_or(0, |m| m.len());
        assert!(len > 0, "lumis {}: no {o}", args.join(" "));
    }
    true
}

#[test]
fn the_readmes_commands_run_as_written() {
    let (_root, checkout) = checkout_copy();
    for args in command_lines(&readme()) {
        run_if_possible(&checkout, &args);
    }
    // The compositing example writes what it says: albedo and Cryptomatte, Blender's names.
    let image = crate::common::exr::read_exr(&checkout.join("materials.exr"));
    let names = crate::common::exr::channel_names(&image);
    for want in [
        "ViewLayer.DiffCol.R",
        "ViewLayer.CryptoObject00.R",
        "ViewLayer.Depth.Z",
    ] {
        assert!(names.iter().any(|n| n == want), "{want} not in {names:?}");
    }
}

/// docs/cli-reference.md as today's binary prints it.
fn reference() -> String {
    let mut s = String::from(
        "# Command-line reference\n\nEvery command's `--help`, exactly as the binary prints it \
         (regenerated by `LUMIS_BLESS=1 cargo test --test it docs::`; a test fails when it is \
         out of date). The same flags in prose, by topic: [cli.md](cli.md).\n",
    );
    for sub in ["", "render", "info", "hits", "merge"] {
        let title = if sub.is_empty() {
            "lumis".to_string()
        } else {
            format!("lumis {sub}")
        };
        s.push_str(&format!("\n## `{title}`\n\n```text\n{}```\n", help(sub)));
    }
    s
}

#[test]
fn the_cli_reference_is_the_binarys_help() {
    let path = repo().join("docs/cli-reference.md");
    let want = reference();
    if std::env::var_os("LUMIS_BLESS").is_some() {
        std::fs::write(&path, &want).unwrap();
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "{} is out of date: run LUMIS_BLESS=1 cargo test --test it docs::",
        Path::new("docs/cli-reference.md").display()
    );
}

/// How the docs' shell commands that are not `lumis` commands start, and why no test runs
/// them as written (each is covered elsewhere or needs what a test machine lacks).
const NOT_RUN: [(&str, &str); 13] = [
    ("[", "the continuation of a synopsis"),
    (
        "sbatch",
        "needs Slurm; CI runs tools/test_slurm.sh on a real single-node cluster",
    ),
    ("kubectl", "needs Kubernetes"),
    (
        "tev",
        "a viewer with a window; tests/it/live_view plays the viewer",
    ),
    (
        "O=/tmp/orig;",
        "builds the paper's original program, outside the repository",
    ),
    (
        ".venv/bin/python",
        "the tools in their venv, which CI runs step by step",
    ),
    (".venv/bin/pip", "installs the Python package, as CI does"),
    ("python3 -m venv", "makes the venv, as CI does"),
    ("cargo", "builds and tests, as CI does"),
    (
        "fuzz/make_corpus.sh",
        "the fuzz corpus; CI runs every fuzz target",
    ),
    (
        "cd fuzz",
        "fuzzing for minutes with the nightly toolchain; CI runs every fuzz target",
    ),
    (
        "LUMIS_QUERIES_",
        "fuzzing for minutes with the nightly toolchain",
    ),
    (
        "QUERY_FUZZ_REPLAY=",
        "replays fuzzing's artifacts, which a clean checkout has none of",
    ),
];

#[test]
fn every_other_docs_command_is_listed_with_why_it_is_not_run() {
    let mut unlisted = Vec::new();
    let docs = super::documents();
    for doc in docs.iter().filter(|d| d.starts_with(repo().join("docs"))) {
        let text = std::fs::read_to_string(doc).unwrap();
        let (mut in_sh, mut continued) = (false, false);
        for line in text.lines() {
            if line.starts_with("```") {
                in_sh = line == "```sh";
                continue;
            }
            let command = line.trim();
            let was_continued = std::mem::replace(&mut continued, command.ends_with('\\'));
            if !in_sh || was_continued || command.is_empty() || command.starts_with('#') {
                continue;
            }
            let lumis =
                command.starts_with("lumis ") || command.starts_with("cargo run --release --");
            if !lumis && !NOT_RUN.iter().any(|(start, _)| command.starts_with(start)) {
                unlisted.push(format!("{}: {command}", doc.display()));
            }
        }
    }
    assert!(
        unlisted.is_empty(),
        "docs commands no test runs and NOT_RUN does not list:\n{}",
        unlisted.join("\n")
    );
}
