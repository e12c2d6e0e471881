#!/usr/bin/env python3
"""Times lumis against Embree (through embreex), one thread each, on the same rays and model.

    .venv/bin/python tools/bench_embree.py MODEL [--runs 5] [--rays 200000]
        [--camera 512x384] [--subdivide N] [--lumis-args "--accel bsp"] [--json out.json]
        [--lumis PATH]

For example, the two measurements in BENCHMARKS.md ("lumis vs Embree (single thread)"):

    .venv/bin/python tools/bench_embree.py ../shared/paper-scenes/models/bunny.orig.m
    .venv/bin/python tools/bench_embree.py ../shared/paper-scenes/models/bunny.orig.m \
        --subdivide 2

MODEL is a .m (the paper's mesh format), .obj, .gltf, .glb, .toml or .scn file with triangles
only (embreex builds triangle meshes here). The Embree side reads it with
tools/lumis_tools/geometry.py, independently of lumis; lumis reads it itself (a bare .m is
wrapped in a one-line TOML scene in a temporary folder). With --subdivide N the model is first
Loop-subdivided N times with trimesh and written to a temporary GLB, which then feeds both
engines (twice on the 69,473-triangle bunny gives 1,111,568 triangles).

Three seeded ray sets (float32 (N, 8): origin, unit direction, t_min 0, t_max inf; made by
lumis_tools/rays.py, bench_*) go to both:
- incoherent: --rays origins uniform on a sphere of twice the bounding-sphere radius around the
  model, each aimed at a uniform random point of its bounding box;
- camera: a --camera W x H pinhole grid (one ray per pixel centre, 40 degrees vertical field of
  view) from a three-quarter view above (azimuth 45, elevation 30 degrees on the +x +y +z side,
  y up), aimed at the middle of the model's outline, as close as keeps every vertex in frame;
- all-miss: the incoherent origins, each ray pointing straight away from the model. Every ray
  misses the root box, so its time is each engine's fixed cost per query (for Embree, embreex's
  loop filling and reading an RTCRayHit per ray; for lumis, its ray set-up and hit record),
  which is part of the other two sets' times too.

Timing: --runs rounds. Each round builds a fresh Embree scene, then for each ray set runs
Embree and lumis in turn (who goes first alternates between rounds):
- Embree: `EmbreeScene.run(origins, dirs, dists, output=True)` (embreex's Cython loop over
  rtcIntersect1, returning t, primID, geomID, u, v and Ng for every ray, the same record lumis
  writes), called twice, the second call timed;
- lumis: one `lumis hits --threads 1 --repeat 2 --rebuild 2 --timings` process, which traces the set twice
  after loading and building; its first pass is dropped as the warm-up.
Throughputs are rays / median seconds over the rounds; the ratio lumis/Embree is of those
throughputs (below 1: lumis is slower). Also printed: the ratio of the fastest passes
("best", the least disturbed by other processes) and each round's own ratio, as a measure of
the noise. Process start-up, file loading, building and the writing of the hits are outside
the trace timings. Interleaving the engines keeps their samples close in time, so load from
other processes on a shared machine moves both rather than the ratio.

Build, separately: Embree's `rtcCommitScene` (embreex commits lazily, so its first `run`, on
one ray, is timed) once per round, against lumis's accelerator build after loading in every
lumis process (`--rebuild 2`: the second of two builds, since Embree's builds after the first
round run in a process that has built before, while a fresh process's first build also pays
for the system handing it new memory; the first builds are printed too); medians.

Threads: before Embree is loaded this process pins itself (and so the lumis processes it
starts, which inherit the mask) to one CPU (--cpu, default the last allowed one). TBB sizes its
pool from the affinity mask, so Embree's BVH build is single-threaded too; the CPU time of each
commit is printed beside its wall time as a check. --no-pin leaves the mask alone: Embree then
builds with all cores (tracing stays on one thread in embreex's loop).

The Embree scene is created with robust=True (RTC_SCENE_FLAG_ROBUST: Embree avoids the
optimisations that reduce arithmetic accuracy, so rays do not slip through shared edges), the
closest match to lumis's watertight triangle test; --no-robust drops it.

Agreement: the hits of both engines are compared per ray (same hit/miss, same triangle id,
t within 1e-4 relative) to show both did the same work. The triangle-id column assumes both
number the triangles in file order, as they do for one mesh (.m, a single-mesh GLB); for other
scenes rely on hit/miss and t.

lumis is --lumis PATH or $LUMIS_BIN (run as they are), else target/release/lumis of this
checkout (refused when older than src/, Cargo.toml or Cargo.lock: `cargo build --release`).
Needs numpy, embreex and trimesh (tools/requirements.txt). Temporary files go to a fresh
temporary folder that is removed at the end. With the defaults a run takes about 5 s on the 69k-triangle bunny and 30 s on the
1.1M-triangle one (--subdivide 2), on 2 cores.
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

# numpy's OpenBLAS starts its threads at import, before main() pins this process, and they spin
# on the other core after each matrix product (the loaders do a few), which would count in the
# CPU time that checks the Embree build is single-threaded. Nothing here needs BLAS threads.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

from . import exitcodes  # noqa: E402
from . import lumis as lumis_run  # noqa: E402
from .embree import EmbreeScene  # noqa: E402
from .geometry import load_geometry  # noqa: E402
from .machine import cpu_info  # noqa: E402
from .rays import bench_all_miss, bench_camera, bench_incoherent  # noqa: E402
from .sizes import wxh  # noqa: E402

T_RTOL = 1e-4


def parse_args(argv=None):
    p = argparse.ArgumentParser(
        description="Single-thread ray throughput of lumis (`lumis hits --threads 1`) against "
        "Embree (embreex, rtcIntersect1) on the same model and the same seeded ray sets; "
        "prints Mrays/s of each, the ratio lumis/Embree, and the build times.",
        epilog="Method:\n" + "\n".join("  " + line for line in __doc__.splitlines()),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("model", type=Path,
                   help="model or scene: .m, .obj, .gltf, .glb, .toml or .scn (triangles only)")
    p.add_argument("--runs", type=int, default=5,
                   help="rounds: each times every ray set once per engine after a warm-up pass, "
                   "and one Embree build; medians are reported; default 5")
    p.add_argument("--rays", type=int, default=200_000,
                   help="rays in the incoherent set (and in the all-miss set); default 200000")
    p.add_argument("--camera", default="512x384", metavar="WxH",
                   help="camera ray grid, one ray per pixel; default 512x384 (196,608 rays)")
    p.add_argument("--subdivide", type=int, default=0, metavar="N",
                   help="Loop-subdivide the model N times (trimesh) into a temporary GLB first; "
                   "default 0")
    p.add_argument("--lumis-instance", action="store_true",
                   help="lumis traces the model as one instance (a TOML `[[instance]]` of it, "
                   "identity placement: two levels) against Embree's flat mesh; the per-ray "
                   "cost of entering an instance")
    p.add_argument("--seed", type=int, default=1, help="seed of the incoherent rays; default 1")
    p.add_argument("--lumis-args", default="", metavar="ARGS",
                   help='extra arguments for `lumis hits`, e.g. "--accel bsp" (default: its '
                   "default, the SAH BVH)")
    p.add_argument("--cpu", type=int, default=None,
                   help="CPU to pin both engines to; default the last one allowed")
    p.add_argument("--no-pin", action="store_true",
                   help="do not pin (Embree's BVH build may then use every core)")
    p.add_argument("--no-robust", action="store_true",
                   help="build the Embree scene without the robust flag")
    p.add_argument("--json", type=Path, metavar="PATH",
                   help="also write every number measured as JSON")
    lumis_run.add_argument(p)
    args = p.parse_args(argv)
    if args.runs < 1:
        p.error("--runs must be at least 1")
    if args.rays < 1:
        p.error("--rays must be at least 1")
    w, h = wxh(p, "--camera", args.camera, "512x384")
    args.camera_size = (w, h)
    if args.subdivide < 0:
        p.error("--subdivide must be >= 0")
    if not args.model.is_file():
        p.error(f"{args.model}: no such file")
    return args


# ---------------------------------------------------------------------------------------------
# Model and rays


def prepare_model(model: Path, subdivide: int, tmp: Path, instance: bool = False):
    """(path lumis loads, float32 (M, 3, 3) triangles for Embree, description)."""
    model = model.resolve()
    geometry = load_geometry(model)
    if len(geometry.spheres):
        raise exitcodes.SetupError(f"{model}: has {len(geometry.spheres)} spheres; this "
                                   "benchmark feeds Embree triangles only")
    if not len(geometry.triangles):
        raise exitcodes.SetupError(f"{model}: no triangles")
    what = f"{model} ({len(geometry.triangles):,} triangles)"
    lumis_scene = model
    if subdivide:
        import trimesh

        tris = geometry.triangles
        mesh = trimesh.Trimesh(vertices=tris.reshape(-1, 3),
                               faces=np.arange(3 * len(tris)).reshape(-1, 3), process=True)
        start = time.perf_counter()
        mesh = mesh.subdivide_loop(iterations=subdivide)
        lumis_scene = tmp / f"{model.stem}.sub{subdivide}.glb"
        mesh.export(lumis_scene)
        print(f"subdivided {subdivide}x in {time.perf_counter() - start:.1f} s -> {lumis_scene}",
              flush=True)
        geometry = load_geometry(lumis_scene)  # both engines read the same file
        what += f", Loop-subdivided {subdivide}x: {len(geometry.triangles):,} triangles"
    elif model.suffix.lower() == ".m":
        lumis_scene = tmp / f"{model.stem}.toml"
        lumis_scene.write_text(f"[[mesh]]\nfile = {json.dumps(str(model))}\n")
    if instance:
        # The model file itself (a bare .m was wrapped in a scene above).
        path = model if model.suffix.lower() == ".m" and not subdivide else lumis_scene
        if path.suffix.lower() in (".toml", ".scn"):
            raise exitcodes.SetupError("--lumis-instance takes a model file, not a scene")
        lumis_scene = tmp / f"{model.stem}.instance.toml"
        lumis_scene.write_text(f"[[mesh]]\nname = \"model\"\nfile = {json.dumps(str(path))}\n"
                               "[[instance]]\nof = \"model\"\n")
        what += "; lumis: one instance of it"
    tris = np.ascontiguousarray(geometry.triangles, np.float32)
    return lumis_scene, tris, what


def ray_sets(tris, n, seed, camera_size):
    """The benchmark's three ray sets for float32 (M, 3, 3) triangles: `n` incoherent and `n`
    all-miss rays of `seed`, and the camera's `camera_size` = (w, h) rays."""
    points = tris.reshape(-1, 3).astype(np.float64)
    lo, hi = points.min(0), points.max(0)
    w, h = camera_size
    return {
        "incoherent": bench_incoherent(lo, hi, n, seed),
        "camera": bench_camera(points, w, h),
        "all-miss": bench_all_miss(lo, hi, n, seed),
    }


# ---------------------------------------------------------------------------------------------
# Engines


class Embree:
    """A fresh EmbreeScene per round (so each round times a build), traced as the oracle does."""

    def __init__(self, tris, robust):
        self.tris, self.robust = tris, robust
        self.scene = None

    def build(self):
        """A fresh scene; returns (wall, cpu) seconds of its commit."""
        self.scene = None
        scene = EmbreeScene(self.tris, robust=self.robust)
        timing = scene.commit()
        self.scene = scene
        return timing

    def trace(self, rays):
        """(seconds, result dict) of one closest-hit pass with full hit records."""
        return self.scene.timed_intersect(rays)


def run_lumis(scene, rays, repeat, extra):
    return lumis_run.hits(scene, rays, threads=1, repeat=repeat, extra=extra)


def agreement(embree_out, lumis_rows):
    """Fractions: same hit/miss; among rays both hit, same triangle id and t within 1e-4."""
    e_hit = embree_out["geomID"] != -1
    l_t = lumis_rows[:, 0].astype(np.float64)
    l_hit = np.isfinite(l_t)
    both = e_hit & l_hit
    e_t = embree_out["tfar"].astype(np.float64)
    same_prim = embree_out["primID"][both] == lumis_rows[both, 1].astype(np.int64)
    close_t = np.abs(e_t[both] - l_t[both]) <= T_RTOL * np.maximum(np.abs(e_t[both]), 1e-30)
    n_both = max(int(both.sum()), 1)
    return {
        "hit_rate_embree": float(e_hit.mean()),
        "hit_rate_lumis": float(l_hit.mean()),
        "same_hit_miss": float((e_hit == l_hit).mean()),
        "both_hit": int(both.sum()),
        "same_prim": float(same_prim.sum() / n_both),
        "t_within_1e-4": float(close_t.sum() / n_both),
    }


# ---------------------------------------------------------------------------------------------


def cpu_model():
    return cpu_info()["model"]


def package_version(name):
    from importlib import metadata

    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "unknown"


def pin(cpu=None):
    """Pins this process to `cpu` (default the last allowed one) and returns it. Call it before
    Embree (and with it TBB) is loaded: TBB sizes its pool from this mask. It is the main
    thread's mask; threads started later (TBB's, the lumis processes) inherit it."""
    allowed = sorted(os.sched_getaffinity(0))
    pinned = cpu if cpu is not None else allowed[-1]
    if pinned not in allowed:
        raise exitcodes.SetupError(f"--cpu {pinned}: not among the allowed CPUs {allowed}")
    os.sched_setaffinity(0, {pinned})
    return pinned


def lumis_revision(explicit):
    """Where the lumis binary comes from, for the printout: --lumis, $LUMIS_BIN, or the commit
    of this checkout (and whether its sources have uncommitted changes)."""
    if explicit:
        return "--lumis"
    if os.environ.get("LUMIS_BIN"):
        return "$LUMIS_BIN"

    def git(*a):
        return subprocess.run(["git", *a], cwd=lumis_run.REPO, capture_output=True,
                              text=True).stdout.strip()

    rev = "commit " + (git("rev-parse", "--short", "HEAD") or "?")
    if git("status", "--porcelain", "--", "src", "crates", "Cargo.toml", "Cargo.lock"):
        rev += " + uncommitted changes in src/ or Cargo.*"
    return rev


def main(argv=None):
    args = parse_args(argv)
    lumis_extra = shlex.split(args.lumis_args)
    pinned = None if args.no_pin else pin(args.cpu)
    lumis_run.use(args.lumis)
    exe = lumis_run.binary()
    rev = lumis_revision(args.lumis)
    print(f"machine: {os.cpu_count()} CPUs ({cpu_model()}); "
          + (f"both engines pinned to CPU {pinned}" if pinned is not None else "not pinned"))
    print(f"lumis: {exe} ({rev}), args: hits --threads 1 --repeat 2 --rebuild 2 "
          f"{' '.join(lumis_extra)}".rstrip())
    print(f"embreex {package_version('embreex')}, robust={not args.no_robust}; "
          f"median of {args.runs} interleaved rounds", flush=True)

    with tempfile.TemporaryDirectory(prefix="bench-embree-") as tmp:
        tmp = Path(tmp)
        lumis_scene, tris, what = prepare_model(args.model, args.subdivide, tmp,
                                               args.lumis_instance)
        print(f"model: {what}", flush=True)
        sets = ray_sets(tris, args.rays, args.seed, args.camera_size)

        # --runs rounds. In each: a fresh Embree scene is built, then for every ray set Embree
        # and one `lumis hits --repeat 2` process take turns (who goes first alternates), each
        # tracing the set twice and timing the second pass. Interleaving keeps the two engines'
        # samples close in time, so load from other processes on this shared machine shifts
        # both rather than the ratio.
        embree = Embree(tris, robust=not args.no_robust)
        builds, lumis_builds, lumis_first_builds, lumis_loads = [], [], [], []
        lumis_memory = {}
        times = {name: {"embree": [], "lumis": []} for name in sets}
        last = {}
        for round_no in range(args.runs):
            builds.append(embree.build())
            for name, rays in sets.items():
                def embree_turn():
                    embree.trace(rays)  # warm-up
                    t, out = embree.trace(rays)
                    times[name]["embree"].append(t)
                    last[name, "embree"] = out

                def lumis_turn():
                    lh = run_lumis(lumis_scene, rays, 2, [*lumis_extra, "--rebuild", "2"])
                    times[name]["lumis"].append(lh.timings["trace_s"][1])
                    lumis_builds.append(lh.timings["build_runs_s"][-1])
                    lumis_first_builds.append(lh.timings["build_runs_s"][0])
                    lumis_loads.append(lh.timings["load_s"])
                    lumis_memory.update({k: lh.timings.get(k) for k in
                                         ("prims", "geometry_bytes", "accel_bytes")})
                    last[name, "lumis"] = lh.rows

                turns = (embree_turn, lumis_turn) if round_no % 2 == 0 else (lumis_turn,
                                                                             embree_turn)
                for turn in turns:
                    turn()
            print(f"round {round_no + 1}/{args.runs} done", flush=True)
        e_build = statistics.median(b[0] for b in builds)
        e_build_cpu = statistics.median(b[1] for b in builds)
        l_build = statistics.median(lumis_builds)

        results = {}
        for name, rays in sets.items():
            n = len(rays)
            e_times, l_times = times[name]["embree"], times[name]["lumis"]
            e_med, l_med = statistics.median(e_times), statistics.median(l_times)
            per_round = [e / l for e, l in zip(e_times, l_times)]
            results[name] = {
                "rays": n,
                "embree_s": e_times,
                "lumis_s": l_times,
                "embree_mrays_s": n / e_med / 1e6,
                "lumis_mrays_s": n / l_med / 1e6,
                "ratio_lumis_embree": e_med / l_med,
                "ratio_per_round": per_round,
                "ratio_best": min(e_times) / min(l_times),
                "agreement": agreement(last[name, "embree"], last[name, "lumis"]),
            }

    print()
    print(f"{'rays':<11} {'count':>9} {'Embree Mrays/s':>15} {'lumis Mrays/s':>14} "
          f"{'lumis/Embree':>13} {'(best)':>7} {'hit rate':>9} {'same hit/miss':>14} "
          f"{'same tri':>9} {'t agrees':>9}")
    for name, r in results.items():
        a = r["agreement"]
        same_prim, close_t = ((f"{a['same_prim']:.4%}", f"{a['t_within_1e-4']:.4%}")
                              if a["both_hit"] else ("-", "-"))
        print(f"{name:<11} {r['rays']:>9,} {r['embree_mrays_s']:>15.2f} "
              f"{r['lumis_mrays_s']:>14.2f} {r['ratio_lumis_embree']:>13.3f} "
              f"{r['ratio_best']:>7.3f} "
              f"{a['hit_rate_embree']:>9.1%} {a['same_hit_miss']:>14.4%} {same_prim:>9} "
              f"{close_t:>9}")
    print()
    top_level = (" (one instance: lumis's build_s is its top level only; the prototype's "
                 "hierarchy is built at load)" if args.lumis_instance else "")
    print(f"build: Embree commit {e_build * 1e3:.1f} ms (CPU time {e_build_cpu * 1e3:.1f} ms), "
          f"lumis build_s {l_build * 1e3:.1f} ms; lumis/Embree build time "
          f"{l_build / e_build:.2f}x (medians of {len(builds)} and {len(lumis_builds)})"
          f"{top_level}")
    print(f"(lumis first build of each process: median "
          f"{statistics.median(lumis_first_builds) * 1e3:.1f} ms; load_s, not in build: median "
          f"{statistics.median(lumis_loads):.2f} s)")
    prims = lumis_memory.get("prims")
    if prims and args.lumis_instance:
        # The top level holds one primitive: per triangle of the model instead, build not
        # measured (above).
        accel, geom = lumis_memory["accel_bytes"], lumis_memory["geometry_bytes"]
        print(f"lumis memory: {(accel + geom) / len(tris):.1f} B/tri of the model (its "
              f"prototype and hierarchy, and the top level's {accel} B)")
    elif prims:
        # Build throughput and memory per triangle, as `lumis hits --timings` reports them.
        print(f"lumis build: {prims / l_build / 1e6:.2f} Mtri/s on one thread "
              f"(Embree: {prims / e_build / 1e6:.2f} Mtri/s)")
        accel, geom = lumis_memory["accel_bytes"], lumis_memory["geometry_bytes"]
        print(f"lumis memory: hierarchy {accel / prims:.1f} B/tri + scene geometry "
              f"{geom / prims:.1f} B/tri = {(accel + geom) / prims:.1f} B/tri")
    print("per-round seconds (and lumis/Embree ratio of each round):")
    for name, r in results.items():
        print(f"  {name}: Embree {' '.join(f'{t:.4f}' for t in r['embree_s'])}; "
              f"lumis {' '.join(f'{t:.4f}' for t in r['lumis_s'])}; "
              f"ratios {' '.join(f'{x:.3f}' for x in r['ratio_per_round'])}")

    if args.json:
        record = {
            "model": what, "lumis_scene": str(lumis_scene), "lumis_args": lumis_extra,
            "runs": args.runs, "pinned_cpu": pinned, "robust": not args.no_robust,
            "cpus": os.cpu_count(), "cpu_model": cpu_model(), "lumis_bin": str(exe),
            "lumis_rev": rev,
            "embree_build_s": [b[0] for b in builds], "embree_build_cpu_s": [b[1] for b in builds],
            "lumis_build_s": lumis_builds, "lumis_first_build_s": lumis_first_builds,
            "lumis_load_s": lumis_loads, "sets": results,
            "lumis_memory": lumis_memory,
        }
        args.json.write_text(json.dumps(record, indent=2) + "\n")


def cli():
    exitcodes.run(main, setup_errors=(OSError,))


if __name__ == "__main__":
    cli()
