"""trimesh's ray queries with lumis's engine (`lumis.trimesh.RayMeshIntersector`) against
trimesh's Embree engine (`trimesh.ray.ray_pyembree`, embreex) on the same mesh, rays and
points, in one process.

    python tools/bench_trimesh.py MODEL [--subdivide N] [--threads 1|all] [--rounds 5]
    python tools/bench_trimesh.py --hard-case

MODEL is read as tools/bench_embree.py reads it (`--subdivide 2`: Loop-subdivided twice by
trimesh, the 1.1M-triangle bunny from bunny.orig.m), then welded into one `trimesh.Trimesh`.
Timed, through the engines' public methods: `intersects_first` and
`intersects_location(..., multiple_hits=True)` on the incoherent rays of
tools/bench_python.py (origins on a sphere around the mesh aimed at uniform points in its
box), `contains_points` on uniform points in the mesh's box. Each round runs every query on
both engines one after the other (interleaved, so machine load hits them alike); medians are
printed with the ratio Embree time / lumis time (above 1: lumis is faster). Each engine's
first query, which builds its scene, is timed apart.

`--threads 1` pins the process to one CPU before anything runs (lumis's pool then has one
worker; trimesh's Embree queries run on the calling thread either way); `--threads all`
leaves the mask alone, as a user gets it.

`--hard-case` prints the correctness figures instead: wrong hit counts on 3,000 lattice rays
through the edges and vertices of python/tests/trimesh_hard_case.py's mesh and wrong
containment answers on 25,000 lattice points, for lumis and trimesh's two engines, against
that module's exact oracle.
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from .bench_embree import prepare_model
from .bench_python import incoherent
from .machine import cpu_summary

ROOT = Path(__file__).resolve().parents[2]


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("model", type=Path, nargs="?")
    p.add_argument("--subdivide", type=int, default=0)
    p.add_argument("--threads", choices=["1", "all"], default="all")
    p.add_argument("--rays", type=int, default=100_000)
    p.add_argument("--points", type=int, default=100_000)
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--hard-case", action="store_true")
    args = p.parse_args(argv)
    if args.model is None and not args.hard_case:
        p.error("give a MODEL or --hard-case")
    return args


def welded_mesh(model: Path, subdivide: int):
    import trimesh

    with tempfile.TemporaryDirectory() as tmp:
        _, tris, what = prepare_model(model, subdivide, Path(tmp))
    tris = np.asarray(tris, np.float64)
    mesh = trimesh.Trimesh(vertices=tris.reshape(-1, 3),
                           faces=np.arange(3 * len(tris)).reshape(-1, 3), process=True)
    return mesh, what


def timed(f):
    start = time.perf_counter()
    result = f()
    return time.perf_counter() - start, result


def bench(args) -> None:
    from trimesh.ray import ray_pyembree

    import lumis
    import lumis.trimesh

    mesh, what = welded_mesh(args.model, args.subdivide)
    print(f"mesh: {what}; welded: {len(mesh.vertices):,} vertices, {len(mesh.faces):,} faces")
    rays = incoherent(np.concatenate([np.zeros((len(mesh.faces), 1)),
                                      mesh.triangles.reshape(-1, 9)], axis=1),
                      args.rays, args.seed)
    origins = rays[:, 0:3].astype(np.float64)
    directions = rays[:, 3:6].astype(np.float64)
    points = np.random.default_rng(args.seed).uniform(*mesh.bounds, size=(args.points, 3))

    engines = {"embree": ray_pyembree.RayMeshIntersector(mesh),
               "lumis": lumis.trimesh.RayMeshIntersector(mesh)}
    contains_kind = ("Scene.contains" if hasattr(lumis.Scene, "contains")
                     else "fallback: intersect_all parity (Scene.contains not in this build)")
    scene_kind = ("Scene.from_arrays" if hasattr(lumis.Scene, "from_arrays")
                  else "fallback: through an OBJ file (Scene.from_arrays not in this build)")
    print(f"lumis scene: {scene_kind}; containment: {contains_kind}")
    for name, engine in engines.items():
        s, _ = timed(lambda: engine.intersects_first(origins[:1], directions[:1]))
        print(f"{name}: first query (scene build) {s:.3f} s")

    queries = {
        "intersects_first": lambda e: e.intersects_first(origins, directions),
        "intersects_location(multiple_hits=True)":
            lambda e: e.intersects_location(origins, directions, multiple_hits=True),
        "contains_points": lambda e: e.contains_points(points),
    }
    times = {(q, n): [] for q in queries for n in engines}
    answers = {}
    for _ in range(args.rounds):
        for q, f in queries.items():
            for n, e in engines.items():
                s, answers[q, n] = timed(lambda: f(e))
                times[q, n].append(s)

    hits = {n: np.bincount(answers["intersects_location(multiple_hits=True)", n][1],
                           minlength=len(origins)) for n in engines}
    print(f"\nrays {len(origins):,}, points {len(points):,}, rounds {args.rounds}, "
          f"threads {args.threads}; CPU: {cpu_summary()}")
    print("| query | Embree (s) | lumis (s) | Embree / lumis |")
    print("|---|---|---|---|")
    for q in queries:
        e, m = statistics.median(times[q, "embree"]), statistics.median(times[q, "lumis"])
        print(f"| `{q}` | {e:.3f} | {m:.3f} | **{e / m:.2f}** |")
    print(f"\nhits (multiple_hits): Embree {hits['embree'].sum():,}, "
          f"lumis {hits['lumis'].sum():,}; "
          f"rays whose count differs: {(hits['embree'] != hits['lumis']).sum():,}")
    first = {n: answers["intersects_first", n] for n in engines}
    inside = {n: answers["contains_points", n] for n in engines}
    print(f"intersects_first differs on {(first['embree'] != first['lumis']).sum():,} rays; "
          f"contains_points on {(inside['embree'] != inside['lumis']).sum():,} points")


def _hard_case_module():
    """python/tests/trimesh_hard_case.py (the package's tests' mesh and oracle), by path."""
    import importlib.util

    path = ROOT / "python" / "tests" / "trimesh_hard_case.py"
    spec = importlib.util.spec_from_file_location("trimesh_hard_case", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def hard_case() -> None:
    import trimesh
    from trimesh.ray import ray_pyembree, ray_triangle

    import lumis.trimesh

    hard = _hard_case_module()

    vertices, faces = hard.mesh_arrays()
    origins, directions = hard.lattice_rays(3000, seed=0)
    counts, _ = hard.crossing_counts(origins, directions)
    traced = counts >= 0
    points = hard.lattice_points(25000, seed=0)
    inside = hard.containment(points)
    surface = np.array([hard._on_surface(p) for p in points])
    print(f"mesh: {len(faces)} triangles; {traced.sum()} rays judged "
          f"({len(origins) - traced.sum()} along the surface set aside); "
          f"{len(points)} points, {surface.sum()} on the surface")
    print("| engine | rays with a wrong hit count | points wrongly contained (on the surface) |")
    print("|---|---|---|")
    for name, engine in (("lumis", lumis.trimesh.RayMeshIntersector),
                         ("trimesh ray_pyembree", ray_pyembree.RayMeshIntersector),
                         ("trimesh ray_triangle", ray_triangle.RayMeshIntersector)):
        mesh = trimesh.Trimesh(vertices, faces, process=False)
        mesh.ray = engine(mesh)
        _, ray, _ = mesh.ray.intersects_location(origins, directions, multiple_hits=True)
        got = np.bincount(ray, minlength=len(origins))
        wrong_rays = int((traced & (got != counts)).sum())
        wrong = mesh.ray.contains_points(points) != inside
        print(f"| {name} | {wrong_rays} of {traced.sum()} | {wrong.sum()} of {len(points)} "
              f"({(wrong & surface).sum()}) |")


def cli(argv=None) -> None:
    args = parse_args(argv)
    if args.threads == "1" and hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    if args.hard_case:
        hard_case()
    else:
        bench(args)


if __name__ == "__main__":
    cli()
