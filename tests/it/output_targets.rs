//! Outputs that are not regular files. For every output of `lumis render`, `lumis hits` and
//! `lumis merge`, an existing FIFO, directory, symlink to `/dev/zero` or `/dev/null`, or a
//! symlink chain to a FIFO is refused before any work, naming the option, the file and what it
//! is; the run exits 1 and leaves the directory exactly as it was (the FIFO a FIFO, the links
//! links, every other output unwritten, no temporary file). A symlink to a regular file, a
//! chain of them, and a dangling symlink whose directory exists are written through: the file
//! at the end gets the new content and the links stay. Each run has a time limit, so a FIFO
//! opened by mistake fails the test instead of hanging it.

#![cfg(unix)]

use crate::support_io as support;

use std::os::unix::fs::symlink;
use std::path::{Path, PathBuf};
use std::time::Duration;
use support::{lumis, lumis_in, mkfifo, rays_npy, snapshot, temps_under, toml_scene};

/// What sits at an output path before the run.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Existing {
    Fifo,
    LinkToDevZero,
    LinkToDevNull,
    Directory,
    /// `target -> hop -> real/fifo`.
    ChainToFifo,
    /// `target -> nodir/new`: the file it names cannot be created.
    DanglingWithoutDirectory,
    /// `target -> real/target` (a regular file).
    LinkToFile,
    /// `target -> hop -> real/target`.
    ChainToFile,
    /// `target -> real/new` (`real/` exists).
    Dangling,
}

use Existing::*;

const REFUSED: [Existing; 6] = [
    Fifo,
    LinkToDevZero,
    LinkToDevNull,
    Directory,
    ChainToFifo,
    DanglingWithoutDirectory,
];
const WRITTEN_THROUGH: [Existing; 3] = [LinkToFile, ChainToFile, Dangling];

impl Existing {
    /// Makes it at `dir/name` (`real/` and `hop.EXT` beside it where it needs them).
    fn make(self, dir: &Path, name: &str) {
        let at = dir.join(name);
        let hop = format!("hop-{name}");
        let real = dir.join("real");
        std::fs::create_dir_all(&real).unwrap();
        match self {
            Fifo => mkfifo(&at),
            LinkToDevZero => symlink("/dev/zero", &at).unwrap(),
            LinkToDevNull => symlink("/dev/null", &at).unwrap(),
            Directory => std::fs::create_dir(&at).unwrap(),
            ChainToFifo => {
                mkfifo(&real.join("fifo"));
                symlink("real/fifo", dir.join(&hop)).unwrap();
                symlink(&hop, &at).unwrap();
            }
            DanglingWithoutDirectory => symlink("nodir/new", &at).unwrap(),
            LinkToFile | ChainToFile => {
                std::fs::write(real.join(name), b"old").unwrap();
                let first = if self == LinkToFile {
                    &at
                } else {
                    &dir.join(&hop)
                };
                symlink(format!("real/{name}"), first).unwrap();
                if self == ChainToFile {
                    symlink(&hop, &at).unwrap();
                }
            }
            Dangling => symlink("real/new", &at).unwrap(),
        }
    }

    /// What the refusal must say besides the option and the path.
    fn says(self) -> &'static [&'static str] {
        match self {
            Fifo => &["not a regular file (a FIFO)"],
            LinkToDevZero => &["/dev/zero", "not a regular file (a character device)"],
            LinkToDevNull => &["/dev/null", "not a regular file (a character device)"],
            Directory => &["not a regular file (a directory)"],
            ChainToFifo => &["real/fifo", "not a regular file (a FIFO)"],
            DanglingWithoutDirectory => &["nodir/new", "the directory nodir does not exist"],
            _ => &[],
        }
    }

    /// The regular file a written-through output ends up in.
    fn written_file(self, dir: &Path, name: &str) -> PathBuf {
        match self {
            Dangling => dir.join("real/new"),
            _ => dir.join("real").join(name),
        }
    }
}

/// A command and its output options, each with the file it writes when it is not under test.
#[derive(Clone, Copy, Debug)]
enum Cmd {
    Render,
    /// `-o` naming a PNG.
    RenderPng,
    Hits,
    Merge,
}

impl Cmd {
    fn outputs(self) -> &'static [(&'static str, &'static str)] {
        match self {
            Cmd::Render => &[
                ("-o", "img.exr"),
                ("--png", "img.png"),
                ("--stats-json", "stats.json"),
            ],
            Cmd::RenderPng => &[("-o", "img.png"), ("--stats-json", "stats.json")],
            Cmd::Hits => &[
                ("--out", "hits.npy"),
                ("--spawn-out", "spawn.npy"),
                ("--triangles-out", "tri.npy"),
                ("--spheres-out", "sph.npy"),
                ("--timings", "timings.json"),
            ],
            Cmd::Merge => &[("-o", "merged.exr"), ("--png", "merged.png")],
        }
    }

    /// The arguments before the outputs; the inputs are written into `dir` (the tiles of a
    /// merge are read from `tiles`, rendered once).
    fn inputs(self, dir: &Path, tiles: &[String]) -> Vec<String> {
        std::fs::write(dir.join("s.toml"), toml_scene("")).unwrap();
        std::fs::write(dir.join("rays.npy"), rays_npy(&[0.0, 5.0])).unwrap();
        let args: Vec<&str> = match self {
            Cmd::Render | Cmd::RenderPng => vec!["render", "s.toml", "-q"],
            Cmd::Hits => vec!["hits", "s.toml", "--rays", "rays.npy"],
            Cmd::Merge => vec!["merge", "-q"],
        };
        let mut args: Vec<String> = args.into_iter().map(String::from).collect();
        if let Cmd::Merge = self {
            args.extend(tiles.iter().cloned());
        }
        args
    }
}

/// Two tiles of the test scene, for `lumis merge`.
fn tiles(dir: &Path) -> Vec<String> {
    std::fs::write(dir.join("s.toml"), toml_scene("")).unwrap();
    (0..2)
        .map(|i| {
            let name = format!("t{i}.exr");
            let tile = format!("{i}/2");
            lumis(
                dir,
                &["render", "s.toml", "-q", "--tile", &tile, "-o", &name],
            )
            .assert_ok();
            dir.join(name).to_string_lossy().into_owned()
        })
        .collect()
}

/// The first bytes of a file of the kind `name` ends in.
fn magic(name: &str) -> &'static [u8] {
    match Path::new(name).extension().and_then(|e| e.to_str()) {
        Some("exr") => &[0x76, 0x2f, 0x31, 0x01],
        Some("png") => b"\x89PNG",
        Some("npy") => b"\x93NUMPY",
        _ => b"{",
    }
}

/// Runs `cmd` with `flag` naming `existing` (made fresh in a new directory, named like the
/// option's usual file) and every other output naming a file holding `old`; checks the outcome
/// (module docs).
fn check(cmd: Cmd, flag: &str, existing: Existing, tiles: &[String]) {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut args = cmd.inputs(d, tiles);
    let mut name = String::new();
    for (f, file) in cmd.outputs() {
        if *f == flag {
            name = format!("target-{file}");
            existing.make(d, &name);
            args.extend([f.to_string(), name.clone()]);
        } else {
            std::fs::write(d.join(file), b"old").unwrap();
            args.extend([f.to_string(), file.to_string()]);
        }
    }
    let case = format!("{cmd:?} {flag} {existing:?}");
    let before = snapshot(d);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let run = lumis(d, &args);
    assert_eq!(
        temps_under(d),
        Vec::<PathBuf>::new(),
        "{case}: temporaries left"
    );
    if REFUSED.contains(&existing) {
        assert_eq!(run.status.code(), Some(1), "{case}: {}", run.stderr);
        let mut says = vec![flag, name.as_str()];
        says.extend(existing.says());
        run.assert_says(&says);
        assert_eq!(snapshot(d), before, "{case}: the directory changed");
        return;
    }
    run.assert_ok();
    let written = existing.written_file(d, &name);
    let bytes = std::fs::read(&written).unwrap();
    assert!(
        bytes.starts_with(magic(&name)),
        "{case}: {written:?} not written"
    );
    // The links are still the links they were; every other output was written.
    for (path, what) in &before {
        if what.starts_with("->") {
            assert_eq!(&snapshot(d)[path], what, "{case}: a link changed");
        }
    }
    for (f, file) in cmd.outputs() {
        if *f != flag {
            let bytes = std::fs::read(d.join(file)).unwrap();
            assert!(bytes.starts_with(magic(file)), "{case}: {file} not written");
        }
    }
}

fn check_every_output(cmd: Cmd, tiles: &[String]) {
    for (flag, _) in cmd.outputs() {
        for existing in REFUSED.into_iter().chain(WRITTEN_THROUGH) {
            check(cmd, flag, existing, tiles);
        }
    }
}

#[test]
fn render_outputs() {
    check_every_output(Cmd::Render, &[]);
    check_every_output(Cmd::RenderPng, &[]);
}

#[test]
fn hits_outputs() {
    check_every_output(Cmd::Hits, &[]);
}

#[test]
fn merge_outputs() {
    let dir = tempfile::tempdir().unwrap();
    check_every_output(Cmd::Merge, &tiles(dir.path()));
}

/// The refusal comes before the render: one of minutes is refused at once.
#[test]
fn refused_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.toml"), toml_scene("")).unwrap();
    mkfifo(&d.join("fifo.png"));
    symlink("/dev/zero", d.join("zero.exr")).unwrap();
    symlink("/dev/null", d.join("null.json")).unwrap();
    let slow = ["--width", "4096", "--height", "4096", "--spp", "8"];
    for out in [
        ["-o", "zero.exr"],
        ["--png", "fifo.png"],
        ["--stats-json", "null.json"],
    ] {
        let args = [&["render", "s.toml"][..], &out, &slow].concat();
        let run = lumis_in(d, &args, Duration::from_secs(5));
        run.assert_error(&[out[0], out[1], "not a regular file"]);
    }
    assert!(!d.join("out.exr").exists() && !d.join("out.png").exists());
}

/// Through links, the old refusals hold: an output leading to an input, or to another output
/// (also one that does not exist yet), is refused.
#[test]
fn links_to_inputs_and_to_other_outputs_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.toml"), toml_scene("")).unwrap();
    symlink("s.toml", d.join("scene.json")).unwrap();
    symlink("hop.json", d.join("chain.json")).unwrap();
    symlink("s.toml", d.join("hop.json")).unwrap();
    symlink("img.exr", d.join("img.json")).unwrap();
    let before = snapshot(d);
    for (json, says) in [
        ("scene.json", "is an input of this run"),
        ("chain.json", "is an input of this run"),
        ("img.json", "is the same file as -o img.exr"),
    ] {
        let args = ["render", "s.toml", "-o", "img.exr", "--stats-json", json];
        let run = lumis(d, &args);
        assert_eq!(run.status.code(), Some(1), "{json}: {}", run.stderr);
        run.assert_says(&[json, says]);
        assert_eq!(snapshot(d), before, "{json}");
    }
}

/// A symlink loop is refused, naming the link.
#[test]
fn a_symlink_loop_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.toml"), toml_scene("")).unwrap();
    symlink("b.exr", d.join("a.exr")).unwrap();
    symlink("a.exr", d.join("b.exr")).unwrap();
    let before = snapshot(d);
    let run = lumis(d, &["render", "s.toml", "-o", "a.exr"]);
    assert_eq!(run.status.code(), Some(1), "{}", run.stderr);
    run.assert_says(&["-o a.exr", "symlink loop"]);
    assert_eq!(snapshot(d), before);
}
