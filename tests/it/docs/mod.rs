//! The README and docs/ as a newcomer meets them (issue 41): the README is short, every
//! relative link in it and in docs/ leads to a file, its command lines use only flags the
//! commands know, its commands run as written, and docs/cli-reference.md is the `--help` of
//! today's binary. The README's Python example runs in python/tests/test_readme.py.

mod commands;

use std::path::{Path, PathBuf};

fn repo() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// README.md, docs/*.md and tools/README.md.
fn documents() -> Vec<PathBuf> {
    let mut docs = vec![repo().join("README.md"), repo().join("tools/README.md")];
    let mut in_docs: Vec<PathBuf> = std::fs::read_dir(repo().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    in_docs.sort();
    docs.extend(in_docs);
    docs
}

/// The targets of the Markdown links `[text](target)` in `text`.
fn link_targets(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find("](") {
        rest = &rest[at + 2..];
        if let Some(end) = rest.find(')') {
            out.push(rest[..end].to_string());
        }
    }
    out
}

#[test]
fn the_readme_fits_a_newcomers_screens() {
    let text = std::fs::read_to_string(repo().join("README.md")).unwrap();
    let lines = text.lines().count();
    assert!(lines <= 150, "README.md has {lines} lines (at most ~150)");
    // The two set-up commands come first.
    let setup = text.find("cargo run --release ").unwrap();
    assert!(setup < text.find("cargo test").unwrap());
    assert!(text[..setup].lines().count() < 25);
}

#[test]
fn every_relative_link_resolves() {
    let mut broken = Vec::new();
    for doc in documents() {
        let text = std::fs::read_to_string(&doc).unwrap();
        for target in link_targets(&text) {
            let target = target.split_whitespace().next().unwrap_or("");
            if target.is_empty()
                || target.starts_with('#')
                || target.contains("://")
                || target.starts_with("mailto:")
            {
                continue;
            }
            let path = target.split('#').next().unwrap();
            if !doc.parent().unwrap().join(path).exists() {
                broken.push(format!("{}: {target}", doc.display()));
            }
        }
    }
    assert!(
        broken.is_empty(),
        "links to nothing:\n{}",
        broken.join("\n")
    );
}

/// Paths of this repository quoted in `code` spans (`` `crates/core/src/...` ``) that name
/// nothing: the docs drift when files move. Not checked: patterns (`*`, `<`, `NAME`), and paths of
/// other projects, listed here with where they belong.
#[test]
fn every_quoted_repository_path_exists() {
    const OTHERS: [&str; 3] = [
        "src/Ipc.cpp",         // tev's source (docs/live-view.md)
        "tests/test_ray.py",   // trimesh's own tests (docs/python.md)
        "fuzz/corpus/queries", // made by fuzz/make_corpus.sh
    ];
    const ROOTS: [&str; 10] = [
        "tests/",
        "crates/",
        "src/",
        "tools/",
        "python/",
        "scenes/",
        "assets/",
        "fuzz/",
        "benches/",
        "examples/",
    ];
    let mut missing = Vec::new();
    for doc in documents() {
        let text = std::fs::read_to_string(&doc).unwrap();
        for span in text.split('`').skip(1).step_by(2) {
            let path = span.trim_end_matches('/');
            let is_path = ROOTS.iter().any(|r| path.starts_with(r))
                && !path.contains(['*', '<', ' ', '#'])
                && !path.contains("NAME")
                && !OTHERS.contains(&path);
            // tools/README.md names its files from tools/ or from the repository root.
            let exists = repo().join(path).exists() || repo().join("tools").join(path).exists();
            if is_path && !exists {
                missing.push(format!("{}: {path}", doc.display()));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "quoted paths that name nothing:\n{}",
        missing.join("\n")
    );
}
