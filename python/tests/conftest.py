"""Shared helpers of the package's tests: the repository's files, the `lumis` binary (to
compare with: `$LUMIS_BIN`, else `target/release/lumis`; the tests that need it skip without
it unless `LUMIS_REQUIRE_CLI=1`, as in CI), `.npy` round trips through `lumis hits`."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
ASSETS = ROOT / "assets"
SCENES = ROOT / "scenes"


def cli_path() -> Path | None:
    env = os.environ.get("LUMIS_BIN")
    if env:
        return Path(env)
    exe = ROOT / "target" / "release" / ("lumis.exe" if os.name == "nt" else "lumis")
    return exe if exe.exists() else None


@pytest.fixture(scope="session")
def cli() -> Path:
    exe = cli_path()
    if exe is None:
        if os.environ.get("LUMIS_REQUIRE_CLI") == "1":
            pytest.fail("LUMIS_REQUIRE_CLI=1 but no lumis binary: run cargo build --release")
        pytest.skip("no lumis binary (cargo build --release, or set LUMIS_BIN)")
    return exe


def run_cli(exe: Path, *args, check=True) -> subprocess.CompletedProcess:
    p = subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True)
    if check and p.returncode != 0:
        raise AssertionError(f"lumis {' '.join(map(str, args))} failed:\n{p.stderr}")
    return p


def cli_error(exe: Path, *args) -> str:
    """The message `lumis` prints after `error: ` (the last line starting with it)."""
    p = run_cli(exe, *args, check=False)
    assert p.returncode == 1, p.stderr
    lines = [line for line in p.stderr.splitlines() if line.startswith("error: ")]
    assert lines, p.stderr
    return lines[-1][len("error: "):]


def cli_hits(exe: Path, tmp: Path, scene: Path, rays: np.ndarray, *flags) -> np.ndarray:
    """`lumis hits` on float32 `(N, 8)` rays: its `(N, 9)` rows."""
    np.save(tmp / "rays.npy", np.ascontiguousarray(rays, np.float32))
    run_cli(exe, "hits", scene, "--rays", tmp / "rays.npy", "--out", tmp / "hits.npy", *flags)
    return np.load(tmp / "hits.npy")


def random_rays(n: int, seed: int, centre=(0.0, 0.0, 0.0), radius=3.0) -> np.ndarray:
    """`(n, 8)` float64 rays from a sphere of `radius` around `centre` towards points near it:
    t_min 0, t_max inf."""
    rng = np.random.default_rng(seed)
    centre = np.asarray(centre, np.float64)
    o = rng.normal(size=(n, 3))
    o = centre + radius * o / np.linalg.norm(o, axis=1, keepdims=True)
    target = centre + rng.uniform(-0.5, 0.5, size=(n, 3)) * radius * 0.6
    rays = np.zeros((n, 8))
    rays[:, 0:3] = o
    rays[:, 3:6] = target - o
    rays[:, 7] = np.inf
    return rays


def bits(a: np.ndarray) -> np.ndarray:
    """Float32 values as their bit patterns (so -0 != +0 and NaNs compare)."""
    return np.ascontiguousarray(a, np.float32).view(np.uint32)
