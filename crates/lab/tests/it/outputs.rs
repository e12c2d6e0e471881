//! The result files of `lumis-lab` (`paper --csv`, `effects --csv`, `accuracy --csv` and
//! `--plot` as SVG and PNG) follow the rules of every lumis output (tests/output_targets.rs):
//! an existing FIFO, directory or symlink to `/dev/zero` is refused before anything is
//! measured (exit 1, naming the option, the file and what it is, the directory left exactly as
//! it was); so is an output that is a scene of the run; a symlink to a regular file is written
//! through, the link kept, with the content the bench prints. No temporary file is left.
//! Refusals are checked with settings that would measure for well over the time limit.

#![cfg(unix)]

use crate::common;
use crate::support_io as support;

use std::os::unix::fs::symlink;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;
use support::{lumis_in, mkfifo, snapshot, temps_under, toml_scene};

/// A Table I file name (`lumis-lab paper` measures only those) holding one sphere.
const PAPER_SCENE: &str = "line.scn";
const SCN: &str = "cameraUp 0.0 1.0 0.0\ncameraPosition 0.0 0.0 1000.0\ncameraLookAt 0.0 0.0 0.0\n\
                   cameraScreenWidth 2500\nlight 400 100 500 0.9\n\
                   sphere 0.0 0.0 0.0 150 FlatColor 0.6 0.2 0.9 null\n";

#[derive(Clone, Copy, Debug, PartialEq)]
enum Bench {
    Paper,
    Effects,
    Accuracy,
}

use Bench::*;

/// One file option of a bench.
#[derive(Clone, Copy, Debug)]
struct Output {
    bench: Bench,
    flag: &'static str,
    /// The file it names.
    name: &'static str,
    /// The other file option given alongside it, and its file: written when the run succeeds,
    /// untouched when it is refused.
    other: Option<(&'static str, &'static str)>,
}

const fn output(
    bench: Bench,
    flag: &'static str,
    name: &'static str,
    other: Option<(&'static str, &'static str)>,
) -> Output {
    Output {
        bench,
        flag,
        name,
        other,
    }
}

/// Every file option of every bench (`lumis-lab load` writes only into its own temporary folder).
const OUTPUTS: [Output; 5] = [
    output(Paper, "--csv", "paper.csv", None),
    output(Effects, "--csv", "effects.csv", None),
    output(Accuracy, "--csv", "acc.csv", Some(("--plot", "acc.svg"))),
    output(Accuracy, "--plot", "acc.svg", Some(("--csv", "acc.csv"))),
    output(Accuracy, "--plot", "acc.png", Some(("--csv", "acc.csv"))),
];

impl Bench {
    /// The arguments before the outputs, with its scene written into `dir`: a run of well
    /// under a second, or (`slow`) one of far more than the time limit.
    fn args(self, dir: &Path, slow: bool) -> Vec<&'static str> {
        std::fs::write(dir.join("s.toml"), toml_scene("")).unwrap();
        std::fs::create_dir_all(dir.join("paper")).unwrap();
        std::fs::write(dir.join("paper").join(PAPER_SCENE), SCN).unwrap();
        let (size, rounds): (&[&str], &str) = if slow {
            (&["--width", "2048", "--height", "2048"], "50")
        } else {
            (&["--width", "8", "--height", "8"], "1")
        };
        let mut args = match self {
            Paper => {
                let scale = if slow { "4" } else { "0.01" };
                let configs = ["--configs", "bsp (baseline)", "--repeat", rounds];
                [
                    &["paper", "--scenes", "paper", "--scale", scale][..],
                    &configs,
                ]
                .concat()
            }
            Effects => [&["effects", "s.toml"][..], size].concat(),
            Accuracy => [&["accuracy", "s.toml"][..], size].concat(),
        };
        if self != Paper {
            args.extend(["--rounds", rounds]);
        }
        args
    }
}

/// Sets up a run of `out`'s bench, in a new directory, with its option naming `out.name`
/// (made beforehand by `make`, given the directory and the path) and its other output naming a
/// file holding `old`; the directory and the arguments.
fn setup(
    out: Output,
    slow: bool,
    make: impl FnOnce(&Path, &Path),
) -> (tempfile::TempDir, Vec<String>) {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut args: Vec<String> = out
        .bench
        .args(d, slow)
        .into_iter()
        .map(String::from)
        .collect();
    make(d, &d.join(out.name));
    args.extend([out.flag.to_string(), out.name.to_string()]);
    if let Some((flag, file)) = out.other {
        std::fs::write(d.join(file), b"old").unwrap();
        args.extend([flag.to_string(), file.to_string()]);
    }
    (dir, args)
}

/// A FIFO, a symlink to `/dev/zero` and a directory at every output: refused at once.
#[test]
fn special_files_are_refused_before_measuring() {
    type Make = fn(&Path, &Path);
    let cases: [(&str, Make, &[&str]); 3] = [
        ("FIFO", |_, at| mkfifo(at), &["not a regular file (a FIFO)"]),
        (
            "link to /dev/zero",
            |_, at| symlink("/dev/zero", at).unwrap(),
            &["/dev/zero", "not a regular file (a character device)"],
        ),
        (
            "directory",
            |_, at| std::fs::create_dir(at).unwrap(),
            &["not a regular file (a directory)"],
        ),
    ];
    for out in OUTPUTS {
        let Output { flag, name, .. } = out;
        for (what, make, says) in cases {
            let case = format!("{out:?}: {what}");
            let (dir, args) = setup(out, true, make);
            let d = dir.path();
            let before = snapshot(d);
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            let run = lumis_in(d, &args, Duration::from_secs(5));
            assert_eq!(run.status.code(), Some(1), "{case}: {}", run.stderr);
            run.assert_says(&[&format!("{flag} {name}")]);
            run.assert_says(says);
            assert_eq!(snapshot(d), before, "{case}: the directory changed");
            assert_eq!(temps_under(d), Vec::<PathBuf>::new(), "{case}");
        }
    }
}

/// An output that is (or links to) a scene the bench reads is refused once the scenes are
/// loaded, still before measuring.
#[test]
fn a_scene_of_the_run_is_refused_before_measuring() {
    for out in OUTPUTS {
        let case = format!("{out:?}");
        let scene = if out.bench == Paper {
            format!("paper/{PAPER_SCENE}")
        } else {
            "s.toml".to_string()
        };
        let (dir, args) = setup(out, true, |_, at| symlink(&scene, at).unwrap());
        let d = dir.path();
        let before = snapshot(d);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let run = lumis_in(d, &args, Duration::from_secs(5));
        assert_eq!(run.status.code(), Some(1), "{case}: {}", run.stderr);
        run.assert_says(&[out.name, "is an input of this run"]);
        assert_eq!(snapshot(d), before, "{case}: the directory changed");
    }
}

/// A symlink to a regular file: the file gets the result, the link stays, the other output is
/// written too; a CSV holds exactly the CSV the bench prints.
#[test]
fn a_link_to_a_regular_file_is_written_through() {
    for out in OUTPUTS {
        let Output { bench, name, .. } = out;
        let case = format!("{out:?}");
        let (dir, args) = setup(out, false, |d, at| {
            std::fs::create_dir(d.join("real")).unwrap();
            std::fs::write(d.join("real").join(name), b"old").unwrap();
            symlink(format!("real/{name}"), at).unwrap();
        });
        let d = dir.path();
        let before = snapshot(d);
        let run = Command::new(env!("CARGO_BIN_EXE_lumis-lab"))
            .args(&args)
            .current_dir(d)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&run.stderr);
        if name.ends_with(".png") && stderr.contains("no TTF font found") {
            // No font on this machine for the PNG's text: refused before measuring instead.
            assert_eq!(snapshot(d), before, "{case}");
            continue;
        }
        common::cli::assert_ok(&run);
        assert_eq!(temps_under(d), Vec::<PathBuf>::new(), "{case}");
        assert_eq!(
            std::fs::read_link(d.join(name)).unwrap(),
            Path::new("real").join(name),
            "{case}: the link changed"
        );
        let written = std::fs::read(d.join("real").join(name)).unwrap();
        let magic: &[u8] = match name.rsplit('.').next() {
            Some("png") => b"\x89PNG",
            Some("svg") => b"<svg",
            _ => b"scene,",
        };
        assert!(written.starts_with(magic), "{case}: not written");
        if bench != Accuracy {
            // The CSV printed after "CSV:" (and a blank line), as it is on stdout.
            let stdout = String::from_utf8_lossy(&run.stdout);
            let printed = stdout.split_once("CSV:\n\n").unwrap().1;
            assert_eq!(format!("{}\n", String::from_utf8_lossy(&written)), printed);
        }
        if let Some((_, file)) = out.other {
            let bytes = std::fs::read(d.join(file)).unwrap();
            assert!(bytes.len() > 100, "{case}: {file} not written");
        }
    }
}
