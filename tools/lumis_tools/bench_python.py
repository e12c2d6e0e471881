"""Throughput of the Python package's `Scene.intersect` against `lumis hits` (its own trace
time, `--timings` `trace_s`) and Embree (embreex `EmbreeScene.run`, query INTERSECT, robust
scene: what trimesh's `intersects_first` calls), on the same numpy rays in one process.

    target/py-venv/bin/python tools/bench_python.py MODEL [--threads 1|all] [--rounds 5]

MODEL: a .m (wrapped in a one-mesh TOML scene), .obj, .gltf, .glb or .toml with triangles.
Rays: the incoherent set of tools/bench_embree.py (origins on a sphere of 0.75 x the bounds'
diagonal around their centre, aimed at uniform points inside them), float32, seeded.

`--threads 1` pins this process (and so `lumis hits`, which inherits the mask) to one CPU, so
Embree's TBB pool has one worker too; lumis runs with threads=1. `--threads all` leaves the
mask alone: every engine uses every allowed CPU. Each round runs the three engines one after
the other (interleaved, so machine load hits them alike): `lumis hits --repeat 2` (the second
run's `trace_s`, warm), `Scene.intersect` timed around the whole Python call (argument
checks, tracing, the numpy result arrays), and Embree's query alone. Medians are printed,
with the Python/CLI and lumis/Embree ratios. Needs `pip install ./python`, embreex, and
target/release/lumis (or $LUMIS_BIN).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]  # the checkout (tools/lumis_tools/ -> ./)


def incoherent(tris, n, seed):
    v = tris[:, 1:].reshape(-1, 3).astype(np.float64)
    lo, hi = v.min(0), v.max(0)
    rng = np.random.default_rng(seed)
    centre, radius = (lo + hi) / 2, 0.75 * np.linalg.norm(hi - lo)
    dirs = rng.normal(size=(n, 3))
    origins = centre + radius * dirs / np.linalg.norm(dirs, axis=1, keepdims=True)
    targets = rng.uniform(lo, hi, size=(n, 3))
    rays = np.zeros((n, 8), np.float32)
    rays[:, 0:3] = origins
    rays[:, 3:6] = targets - origins
    rays[:, 7] = np.inf
    return rays


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("model", type=Path)
    p.add_argument("--threads", choices=["1", "all"], default="1")
    p.add_argument("--rays", type=int, default=200_000)
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--seed", type=int, default=1)
    args = p.parse_args(argv)
    single = args.threads == "1"
    if single:
        os.sched_setaffinity(0, {max(os.sched_getaffinity(0))})
    import lumis  # after pinning
    from embreex import rtcore_scene as rtcs
    from embreex.mesh_construction import TriangleMesh

    exe = Path(os.environ.get("LUMIS_BIN", ROOT / "target" / "release" / "lumis"))
    tmp = Path(tempfile.mkdtemp())
    model = args.model.resolve()
    if model.suffix.lower() == ".m":
        scene_path = tmp / f"{model.stem}.toml"
        scene_path.write_text(f"[[mesh]]\nfile = {json.dumps(str(model))}\n")
    else:
        scene_path = model
    scene = lumis.load(scene_path)
    tris = scene.triangles()
    rays = incoherent(tris, args.rays, args.seed)
    np.save(tmp / "rays.npy", rays)
    o, d = rays[:, 0:3], rays[:, 3:6]  # strided views: read in place
    threads = 1 if single else None
    cli_threads = ["--threads", "1"] if single else []

    emb = rtcs.EmbreeScene(robust=True)
    verts = np.ascontiguousarray(tris[:, 1:].reshape(-1, 3), np.float32)
    mesh = TriangleMesh(emb, verts, np.arange(len(verts), dtype=np.int32).reshape(-1, 3))  # noqa: F841
    eo, ed = np.ascontiguousarray(o), np.ascontiguousarray(d)
    emb.run(eo[:1], ed[:1])  # commit
    h = scene.intersect(o, d, threads=threads)  # builds the accelerator once
    # The same answers: Embree's triangle on every ray (random rays meet no edge here).
    prim = emb.run(eo, ed)
    agree = float(np.mean(np.where(prim >= 0, tris[np.maximum(prim, 0), 0], -1) == h.prim_id))

    times = {"cli": [], "python": [], "embree": []}
    for r in range(args.rounds):
        subprocess.run(
            [str(exe), "hits", str(scene_path), "--rays", str(tmp / "rays.npy"), "--out",
             str(tmp / "hits.npy"), "--repeat", "2", "--timings", str(tmp / "t.json"),
             *cli_threads], check=True)
        times["cli"].append(json.loads((tmp / "t.json").read_text())["trace_s"][1])
        start = time.perf_counter()
        scene.intersect(o, d, threads=threads)
        times["python"].append(time.perf_counter() - start)
        start = time.perf_counter()
        emb.run(eo, ed)
        times["embree"].append(time.perf_counter() - start)
    cli_rows = np.load(tmp / "hits.npy")
    same = np.array_equal(cli_rows.view(np.uint32), h.rows().view(np.uint32))
    rate = {k: args.rays / statistics.median(v) / 1e6 for k, v in times.items()}
    cpu = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo")
                if line.startswith("model name")), "?")
    print(f"model {args.model} ({len(tris):,} triangles), {args.rays:,} incoherent rays, "
          f"threads {args.threads} (affinity {sorted(os.sched_getaffinity(0))}), "
          f"{args.rounds} interleaved rounds, CPU {cpu}")
    print(f"python rows == lumis hits rows bit for bit: {same}; Embree's triangle on "
          f"{agree:.4%} of rays")
    for k, v in times.items():
        print(f"  {k:7s} median {statistics.median(v) * 1e3:8.2f} ms = {rate[k]:6.2f} Mrays/s  "
              f"(rounds: {', '.join(f'{x * 1e3:.1f}' for x in v)})")
    print(f"python / lumis hits = {rate['python'] / rate['cli']:.3f}; "
          f"python / Embree = {rate['python'] / rate['embree']:.3f}")
    return 0 if same else 1


def cli():
    """Entry point (tools/bench_python.py, lumis-bench-python)."""
    sys.exit(main())


if __name__ == "__main__":
    cli()
