"""Instructions per ray, lumis beside Embree, counted by callgrind on the same rays: the
repeatable measure of per-ray cost on this noisy machine (BENCHMARKS.md, Phase 14).

    target/tools-venv/bin/python tools/bench_instructions.py MODEL [--subdivide N] [--rays N]

The ray sets are those of tools/bench_embree.py (incoherent, camera, all-miss; same seed and
camera), each cut to every k-th ray so that about --rays remain (default 20,000).

- lumis: `lumis hits SCENE --rays R.npy --threads 1 --repeat N` under callgrind, N = 1 and 3;
  per ray = (count(3) - count(1)) / 2 / rays, so loading, building and writing cancel and what
  remains is the query with its batch bookkeeping (the rows `lumis hits` fills).
- Embree: a Python process that builds an embreex scene (robust, as the benchmark uses) and
  traces the rays once, under callgrind with --toggle-collect on Embree's `rtcIntersect1`:
  only the instructions inside Embree's per-ray entry point count (not embreex's Cython loop
  around it, not Python, not the build, which embreex commits before the first query).

Both are pinned to one CPU and traced single-threaded. Needs valgrind, numpy, embreex,
trimesh (for --subdivide) and target/release/lumis (or --lumis / $LUMIS_BIN).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from . import exitcodes
from . import lumis as lumis_run
from .bench_embree import prepare_model, ray_sets

# Run with tools/ on PYTHONPATH (the package need not be installed).
EMBREE_SCRIPT = """
import numpy as np
from lumis_tools.embree import EmbreeScene
tris = np.load({tris!r})
rays = np.load({rays!r})
scene = EmbreeScene(tris, robust={robust!r})
scene.commit()
scene.intersect(rays)
"""


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("model", type=Path, help="a .m, .obj, .gltf, .glb or .toml of triangles")
    p.add_argument("--subdivide", type=int, default=0, metavar="N",
                   help="Loop-subdivide N times first (2: the 1.1M bunny)")
    p.add_argument("--rays", type=int, default=20_000, help="rays per set (default 20,000)")
    p.add_argument("--sets", default="incoherent,camera,all-miss",
                   help="comma-separated subset of incoherent,camera,all-miss")
    p.add_argument("--engines", default="lumis,embree", help="lumis, embree or both")
    p.add_argument("--no-robust", action="store_true", help="Embree without its robust flag")
    p.add_argument("--lumis-args", default="", help="extra arguments for `lumis hits`")
    p.add_argument("--json", type=Path, help="also write the table as JSON here")
    lumis_run.add_argument(p)
    return p.parse_args(argv)


def callgrind_total(out_file: Path) -> int:
    """The event total of a callgrind output file (its `totals:` / `summary:` line)."""
    text = out_file.read_text(errors="replace")
    m = re.search(r"^(?:totals|summary):\s*(\d+)", text, re.M)
    if not m:
        raise exitcodes.SetupError(f"{out_file}: no totals line")
    return int(m.group(1))


def callgrind(cmd, out_file: Path, extra=(), env=None):
    full = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out_file}", *extra, *cmd]
    done = subprocess.run(full, capture_output=True, text=True, env=env)
    if done.returncode != 0:
        raise exitcodes.SetupError(f"callgrind failed ({done.returncode}): {' '.join(full)}\n"
                                   + done.stderr[-2000:])
    return callgrind_total(out_file)


def lumis_per_ray(exe, scene, rays_npy, n, tmp: Path, extra):
    counts = []
    for repeat in (1, 3):
        cmd = [str(exe), "hits", str(scene), "--rays", str(rays_npy), "--out",
               str(tmp / "hits.npy"), "--threads", "1", "--repeat", str(repeat), *extra]
        counts.append(callgrind(cmd, tmp / f"lumis.{repeat}.out"))
    return (counts[1] - counts[0]) / 2 / n


def embree_per_ray(tris_npy, rays_npy, n, tmp: Path, robust):
    script = tmp / "embree_run.py"
    script.write_text(EMBREE_SCRIPT.format(tris=str(tris_npy), rays=str(rays_npy),
                                           robust=robust))
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[1]))
    total = callgrind([sys.executable, str(script)], tmp / "embree.out",
                      ["--toggle-collect=rtcIntersect1"], env=env)
    # The commit's one probe ray is traced through rtcIntersect1 too.
    return total / (n + 1)


def thin(rays, n):
    step = max(1, len(rays) // n)
    return np.ascontiguousarray(rays[::step][:n])


def main(argv=None):
    args = parse_args(argv)
    lumis_run.use(args.lumis)
    engines = set(args.engines.split(","))
    os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[-1]})
    with tempfile.TemporaryDirectory(prefix="bench-instr-") as tmp:
        tmp = Path(tmp)
        scene, tris, what = prepare_model(args.model, args.subdivide, tmp)
        print(f"model: {what}", flush=True)
        # bench_embree's default sets, thinned below.
        sets = ray_sets(tris, 200_000, 1, (512, 384))
        tris_npy = tmp / "tris.npy"
        np.save(tris_npy, tris)
        table = {}
        for name in args.sets.split(","):
            rays = thin(sets[name].astype(np.float32), args.rays)
            rays_npy = tmp / f"{name}.npy"
            np.save(rays_npy, rays)
            row = {"rays": len(rays)}
            if "lumis" in engines:
                row["lumis"] = lumis_per_ray(lumis_run.binary(), scene, rays_npy, len(rays),
                                             tmp, args.lumis_args.split())
            if "embree" in engines:
                row["embree"] = embree_per_ray(tris_npy, rays_npy, len(rays), tmp,
                                               not args.no_robust)
            if "lumis" in row and "embree" in row:
                row["lumis/embree"] = row["lumis"] / row["embree"]
            table[name] = row
            print(f"{name:>10}: " + ", ".join(
                f"{k} {v:,.1f}" if isinstance(v, float) else f"{k} {v:,}"
                for k, v in row.items()), flush=True)
        if args.json:
            args.json.write_text(json.dumps({"model": what, "sets": table}, indent=2))


def cli():
    exitcodes.run(main)


if __name__ == "__main__":
    cli()
