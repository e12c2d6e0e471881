"""The paper's original C++ program and its Table I scenes, as the side-by-side tools use them:
building the original's variants, running one, reading the images both programs write.

numpy and Pillow are imported only by the functions that need them, so a tool can report that
they are missing (and skip) instead of failing at import.
"""

from __future__ import annotations

import os
import subprocess
import time
from pathlib import Path

from . import REPO
SHARED = REPO.parent / "shared"
SCENES_DIR = SHARED / "paper-scenes" / "scenes"
ORIGINAL_DIR = SHARED / "paper-original"

# The 11 figures of the paper's Table I (../shared/paper-scenes/README.md), in its order.
TABLE_I = [
    "allMaterials",
    "ballsInAPit",
    "ballsOnAPlane",
    "ballsOnAPlaneClose",
    "line",
    "lineFar",
    "modelTest2",
    "texturesInYoFace",
    "triangleSpheres",
    "triangleTest1",
    "tumbledStones",
]

# The executables build.sh makes, one per copy of the program in the original's repository
# (../shared/paper-original/README.md): baseline BSP, BSMP, and scale lights on either.
VARIANTS = ["bsp", "median", "seg2", "seg4096", "median_seg2", "median_seg4096"]

# The paper's depth complexity (lens rays per sample). The original takes it from its command
# line; lumis's .scn loader defaults to the same 5, and `lumis render` has no flag for it.
LENS_RAYS = 5


def build_original(out_dir: Path, log: Path | None = None) -> Path:
    """Builds every variant of the original into `out_dir` with its own build.sh (from the
    source tarball in ../shared/paper-original); returns `out_dir`. The build's output goes to
    `log` (default out_dir/build.log) and is shown when it fails."""
    out_dir.mkdir(parents=True, exist_ok=True)
    log = log or out_dir / "build.log"
    # build.sh compiles each variant with make -j$JOBS; it keeps its own default (all cores).
    with open(log, "w") as f:
        p = subprocess.run([str(ORIGINAL_DIR / "build.sh"),
                            str(ORIGINAL_DIR / "original-src.tar.gz"), str(out_dir)],
                           stdout=f, stderr=subprocess.STDOUT)
    if p.returncode != 0:
        raise RuntimeError(f"build.sh failed (exit {p.returncode}):\n{log.read_text()}")
    return out_dir


def run_original(exe: Path, scene: Path, out_tga: Path, *, width: int, height: int,
                 spp: int = 1, lens_rays: int = LENS_RAYS, threads: int = 2,
                 scenes_dir: Path = SCENES_DIR,
                 timeout: float | None = None) -> tuple[float, str]:
    """Renders `scene` with one variant of the original; returns (wall seconds of the process,
    its standard output, which ends with `Rays cast: N`). After `timeout` seconds the process
    is killed and subprocess.TimeoutExpired raised."""
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    # The original opens model paths relative to its working directory, so it runs from the
    # scene folder, and the scene and output are given as absolute paths.
    cmd = [str(exe), str(Path(scene).resolve()), str(spp), str(lens_rays),
           str(Path(out_tga).resolve()), str(width), str(height)]
    start = time.perf_counter()
    p = subprocess.run(cmd, cwd=scenes_dir, env=env, capture_output=True, text=True,
                       timeout=timeout)
    seconds = time.perf_counter() - start
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed (exit {p.returncode}):\n{p.stderr}")
    return seconds, p.stdout


def rays_cast(stdout: str) -> int | None:
    """The ray count the original prints at the end (`Rays cast: N`), if it did."""
    for line in reversed(stdout.splitlines()):
        if line.startswith("Rays cast:"):
            return int(line.split(":", 1)[1])
    return None


def load_rgb(path: Path):
    """An image as an int16 (H, W, 3) array of 8-bit levels (room for signed differences)."""
    import numpy as np
    from PIL import Image

    return np.asarray(Image.open(path).convert("RGB"), dtype=np.int16)


def mean_abs_diff(a, b) -> float:
    """Mean absolute difference over all pixels and channels, in 8-bit levels."""
    import numpy as np

    if a.shape != b.shape:
        raise ValueError(f"size mismatch {a.shape} vs {b.shape}")
    return float(np.abs(a - b).mean())


def fraction_over(a, b, levels: int) -> float:
    """Fraction of pixels whose largest channel difference exceeds `levels` (8-bit levels)."""
    import numpy as np

    if a.shape != b.shape:
        raise ValueError(f"size mismatch {a.shape} vs {b.shape}")
    return float((np.abs(a - b).max(axis=2) > levels).mean())
