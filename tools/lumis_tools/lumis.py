"""Runs the lumis binary: `lumis hits` for ray queries and primitive dumps, `lumis render`."""

from __future__ import annotations

import json
import os
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import REPO
from .exitcodes import SetupError

# Inputs of the release build: a binary older than the newest of them may not be the code under
# test. Files, or folders searched recursively, relative to the repository.
BUILD_INPUTS = ("src", "crates", "Cargo.toml", "Cargo.lock")

# Set by --lumis PATH (see add_argument): an explicit binary, used as it is.
_explicit: Path | None = None


class LumisError(SetupError):
    """lumis failed; the message carries its stderr. The check could not be made: status 2."""


class StaleBinary(SetupError):
    """target/release/lumis is older than a source file it is built from."""


def add_argument(parser):
    """The `--lumis PATH` option every tool that runs lumis has."""
    parser.add_argument("--lumis", type=Path, metavar="PATH",
                        help="the lumis binary to run, as it is (default: $LUMIS_BIN, else "
                        "target/release/lumis of this checkout, built when missing and refused "
                        "when older than src/, Cargo.toml or Cargo.lock)")


def use(path):
    """Runs `path` from now on, without the staleness check (for --lumis PATH)."""
    global _explicit
    _explicit = Path(path) if path is not None else None


def newer_input(exe: Path, repo: Path):
    """The newest build input (see BUILD_INPUTS) modified after `exe`, or None."""
    built = exe.stat().st_mtime
    newest, newest_t = None, built
    for name in BUILD_INPUTS:
        top = repo / name
        files = top.rglob("*") if top.is_dir() else [top]
        for f in files:
            if f.is_file() and f.stat().st_mtime > newest_t:
                newest, newest_t = f, f.stat().st_mtime
    return newest


def binary() -> Path:
    """The binary to run: --lumis PATH, else `$LUMIS_BIN` (both as they are), else the release
    build in this checkout: built with `cargo build --release` when missing, refused (status 2)
    when a source file is newer, so that a check or a benchmark never reports on old code."""
    if _explicit is not None:
        return _explicit
    env = os.environ.get("LUMIS_BIN")
    if env:
        return Path(env)
    exe = REPO / "target" / "release" / "lumis"
    if not exe.exists():
        p = subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=REPO)
        if p.returncode != 0 or not exe.exists():
            raise SetupError(f"`cargo build --release` failed (exit {p.returncode}) in {REPO}")
    stale = newer_input(exe, REPO)
    if stale is not None:
        raise StaleBinary(
            f"{exe} is older than {stale.relative_to(REPO)}: run `cargo build --release` "
            "first (or pass --lumis PATH, or set LUMIS_BIN, to run a binary as it is)")
    return exe


def run(args, what="lumis"):
    """Runs lumis with `args`; raises LumisError with its stderr on failure."""
    cmd = [str(binary()), *map(str, args)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise LumisError(f"{what} failed (exit {p.returncode}): {' '.join(cmd)}\n{p.stderr}")
    return p


@dataclass
class LumisHits:
    """Rows of `lumis hits` (see src/cli/hits/records.rs): t, prim, object, u, v, normal xyz, kind."""

    rows: np.ndarray
    timings: dict | None = None

    @property
    def t(self):
        return self.rows[:, 0].astype(np.float64)

    @property
    def prim(self):
        return self.rows[:, 1].astype(np.int64)

    @property
    def kind(self):
        return self.rows[:, 8].astype(np.int64)

    @property
    def normal(self):
        return self.rows[:, 5:8].astype(np.float64)


def hits(scene, rays: np.ndarray, *, any_hit=False, threads=None, repeat=1, extra=()):
    """Traces `(N, 8)` float32 rays through `lumis hits`; with `repeat > 1` the timings of every
    run come back in `.timings` (keys rays, load_s, build_s, trace_s)."""
    with tempfile.TemporaryDirectory(prefix="lumis-hits-") as tmp:
        tmp = Path(tmp)
        np.save(tmp / "rays.npy", np.ascontiguousarray(rays, np.float32))
        args = ["hits", scene, "--rays", tmp / "rays.npy", "--out", tmp / "hits.npy",
                "--timings", tmp / "t.json", "--repeat", repeat, *extra]
        if any_hit:
            args.append("--any-hit")
        if threads is not None:
            args += ["--threads", threads]
        run(args, "lumis hits")
        return LumisHits(np.load(tmp / "hits.npy"), json.loads((tmp / "t.json").read_text()))


def primitives(scene):
    """lumis's own view of the scene: triangles `(M, 10)` and spheres `(K, 5)` rows."""
    with tempfile.TemporaryDirectory(prefix="lumis-prims-") as tmp:
        tmp = Path(tmp)
        np.save(tmp / "rays.npy", np.zeros((0, 8), np.float32))
        run(["hits", scene, "--rays", tmp / "rays.npy", "--out", tmp / "hits.npy",
             "--triangles-out", tmp / "tris.npy", "--spheres-out", tmp / "spheres.npy"],
            "lumis hits")
        return np.load(tmp / "tris.npy"), np.load(tmp / "spheres.npy")
