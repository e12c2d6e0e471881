"""Runs the lumis binary: `lumis hits` for ray queries and primitive dumps, `lumis render`."""

from __future__ import annotations

import json
import os
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]


class LumisError(Exception):
    """lumis failed; the message carries its stderr."""


def binary() -> Path:
    """`$LUMIS_BIN`, else the release build in this checkout (built on first use)."""
    env = os.environ.get("LUMIS_BIN")
    if env:
        return Path(env)
    exe = REPO / "target" / "release" / "lumis"
    if not exe.exists():
        subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=REPO, check=True)
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
    """Rows of `lumis hits` (see src/hits.rs): t, prim, object, u, v, normal xyz, kind."""

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
