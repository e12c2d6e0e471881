"""lumis for the tools: ray queries and primitive dumps in process through the Python package
(`import lumis`, distribution lumis-rt, python/) where it is installed, else through the binary
(`lumis hits`); renders through the binary (`lumis render`). Every tool keeps at least one run
through the binary (`via="cli"`) so the command's own paths stay covered."""

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
    """Runs lumis with `args`; raises LumisError with its stderr on failure.

    `render` and `hits` of a glTF file run with `--flatten-instances`: the cross-checks'
    oracles read the file's world-space triangles with their own loader and compare lumis's
    primitive ids in that flat numbering (an instance's hit names its prototype's primitive).
    Instanced answers are checked against flattened ones and against brute force over
    instances by the Rust tests (tests/it/instances, gltf_instancing)."""
    args = [str(a) for a in args]
    if args[:1] in (["render"], ["hits"]) and len(args) > 1 \
            and args[1].lower().endswith((".gltf", ".glb")):
        args.insert(2, "--flatten-instances")
    cmd = [str(binary()), *args]
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


def package():
    """The `lumis` Python package (lumis-rt) where it is installed, else None."""
    try:
        import lumis as pkg  # the installed package, not this module (absolute import)
    except ImportError:
        return None
    return pkg if hasattr(pkg, "load") else None


# `lumis hits` flags with a keyword argument of `Scene.intersect` / `Scene.occluded`.
_KEYWORDS = {"--accel": "accel", "--precision": "precision"}


def _keywords(extra):
    """`extra` flags as query keyword arguments, or None when one has no counterpart."""
    kw, args = {}, [str(a) for a in extra]
    while args:
        flag = args.pop(0)
        name, _, value = flag.partition("=")
        if name not in _KEYWORDS:
            return None
        if not value:
            if not args:
                return None
            value = args.pop(0)
        kw[_KEYWORDS[name]] = value
    return kw


_scenes: dict = {}


def _loaded(pkg, scene):
    """The package's scene for `scene`, loaded once per process."""
    key = str(scene)
    if key not in _scenes:
        # Flattened, as `run` runs glTF files: the oracles number primitives flat.
        _scenes[key] = pkg.load(key, flatten_instances=key.lower().endswith((".gltf", ".glb")))
    return _scenes[key]


def hits(scene, rays: np.ndarray, *, any_hit=False, threads=None, repeat=1, extra=(), via="auto"):
    """Traces `(N, 8)` float32 rays (origin, direction, t_min, t_max) as `lumis hits` does.

    `via`: "package" (in process through `import lumis`: the same library function as the
    command, the same rows bit for bit), "cli" (`lumis hits` in a subprocess), or "auto": the
    package where it is installed and every `extra` flag has a keyword counterpart, else the
    command. With `repeat > 1` (timing, the command only) the timings of every run come back in
    `.timings` (keys rays, load_s, build_s, trace_s). In process, an any-hit row has `t` 0
    where a blocker was found (the package reports only whether) and inf elsewhere."""
    pkg = package() if via in ("auto", "package") else None
    kw = _keywords(extra)
    if via == "package" and (pkg is None or kw is None):
        raise SetupError("the lumis Python package is not installed (pip install ./python), "
                         f"or a flag has no keyword counterpart: {list(extra)}")
    if pkg is not None and kw is not None and repeat == 1:
        rays = np.ascontiguousarray(rays, np.float32)
        s = _loaded(pkg, scene)
        o, d, t0, t1 = rays[:, 0:3], rays[:, 3:6], rays[:, 6], rays[:, 7]
        if threads is not None:
            kw["threads"] = int(threads)
        if any_hit:
            blocked = np.asarray(s.occluded(o, d, t0, t1, **kw), bool)
            # The command's any-hit rows: t, then no ids (-1), zeros, no kind (-1).
            rows = np.zeros((len(rays), 9), np.float32)
            rows[:, [1, 2, 8]] = -1.0
            rows[:, 0] = np.where(blocked, 0.0, np.inf)
            return LumisHits(rows)
        return LumisHits(np.asarray(s.intersect(o, d, t0, t1, **kw).rows(), np.float32))
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


def primitives(scene, via="auto"):
    """lumis's own view of the scene: triangles `(M, 10)` and spheres `(K, 5)` rows (in
    process through the package where installed, unless `via="cli"`)."""
    pkg = package() if via != "cli" else None
    if pkg is not None:
        s = _loaded(pkg, scene)
        return np.asarray(s.triangles(), np.float32), np.asarray(s.spheres(), np.float32)
    with tempfile.TemporaryDirectory(prefix="lumis-prims-") as tmp:
        tmp = Path(tmp)
        np.save(tmp / "rays.npy", np.zeros((0, 8), np.float32))
        run(["hits", scene, "--rays", tmp / "rays.npy", "--out", tmp / "hits.npy",
             "--triangles-out", tmp / "tris.npy", "--spheres-out", tmp / "spheres.npy"],
            "lumis hits")
        return np.load(tmp / "tris.npy"), np.load(tmp / "spheres.npy")
