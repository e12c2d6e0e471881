"""The guard against benchmarking or checking old code (lumis_tools.lumis.binary): a
target/release/lumis older than src/, crates/, Cargo.toml or Cargo.lock is refused, an explicit binary
is run as it is."""

from __future__ import annotations

import os

import pytest

from lumis_tools import lumis


@pytest.fixture
def checkout(tmp_path, monkeypatch):
    """A fake checkout: src/, crates/, Cargo.*, a release binary; everything at t = 1000 s."""
    (tmp_path / "src" / "cli").mkdir(parents=True)
    (tmp_path / "crates" / "core" / "src").mkdir(parents=True)
    files = [tmp_path / "src" / "main.rs", tmp_path / "src" / "cli" / "hits.rs",
             tmp_path / "crates" / "core" / "src" / "lib.rs",
             tmp_path / "Cargo.toml", tmp_path / "Cargo.lock", tmp_path / "README.md"]
    exe = tmp_path / "target" / "release" / "lumis"
    exe.parent.mkdir(parents=True)
    for f in [*files, exe]:
        f.write_text("x")
        os.utime(f, (1000, 1000))
    monkeypatch.setattr(lumis, "REPO", tmp_path)
    monkeypatch.delenv("LUMIS_BIN", raising=False)
    monkeypatch.setattr(lumis, "_explicit", None)
    return tmp_path, exe


def touch(path, t):
    os.utime(path, (t, t))


def test_up_to_date_binary_is_used(checkout):
    repo, exe = checkout
    touch(repo / "README.md", 5000)  # not a build input
    assert lumis.newer_input(exe, repo) is None
    assert lumis.binary() == exe


@pytest.mark.parametrize("changed", ["src/cli/hits.rs", "crates/core/src/lib.rs", "Cargo.toml",
                                     "Cargo.lock"])
def test_newer_input_refuses_the_binary(checkout, changed):
    repo, exe = checkout
    touch(repo / changed, 2000)
    assert lumis.newer_input(exe, repo) == repo / changed
    with pytest.raises(lumis.StaleBinary, match=f"older than {changed}.*cargo build --release"):
        lumis.binary()


def test_explicit_binary_skips_the_check(checkout, monkeypatch):
    repo, exe = checkout
    touch(repo / "src" / "main.rs", 2000)
    other = repo / "lumis-before"
    lumis.use(other)
    assert lumis.binary() == other
    lumis.use(None)
    monkeypatch.setenv("LUMIS_BIN", str(other))
    assert lumis.binary() == other
