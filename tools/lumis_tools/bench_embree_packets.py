#!/usr/bin/env python3
"""Embree's 8-wide packet kernel (`rtcIntersect8`) beside its single-ray one (`rtcIntersect1`)
and lumis's single rays and packets (`lumis hits --packets`), one thread each, on
bench_embree's camera rays.

    .venv/bin/python tools/bench_embree_packets.py MODEL [--runs 5] [--camera 512x384]
        [--subdivide N] [--lumis-args ARGS] [--json out.json] [--lumis PATH]

For example, on the two bunnies of BENCHMARKS.md:

    .venv/bin/python tools/bench_embree_packets.py ../shared/paper-scenes/models/bunny.orig.m
    .venv/bin/python tools/bench_embree_packets.py ../shared/paper-scenes/models/bunny.orig.m \
        --subdivide 2

MODEL, --subdivide and the rays are bench_embree's (its prepare_model and ray_sets): the camera
set, a --camera W x H pinhole grid with one ray per pixel centre in row-major order.

Engines (lumis_tools/embree_native.py has the details of the Embree side):
- Embree-1: rtcIntersect1 on every ray in turn, in a C loop compiled at run time (embreex's
  own copy of libembree4, driven through ctypes; the loops are native because a Python loop
  costs about a microsecond per call and would measure ctypes, not Embree);
- Embree-8: rtcIntersect8 on packets of 8 rays, each packet a 4 x 2 tile of pixels (4 wide, 2
  tall; tiles row by row; where W is not a multiple of 4 or H of 2 the edge packets are partly
  filled and their empty lanes masked off by the valid mask), with Embree's default query
  arguments (RTC_RAY_QUERY_FLAG_INCOHERENT, as rtcIntersect1 is called);
- Embree-8c: the same packets with RTC_RAY_QUERY_FLAG_COHERENT, which lets Embree's hybrid
  packet traversal keep all 8 rays together longer before it falls back to single rays;
- embreex-1: embreex's Cython loop over rtcIntersect1 (`EmbreeScene.run`), the figure
  bench_embree reports, for reference: its loop costs more per ray than the C one;
- lumis: one `lumis hits --threads 1 --repeat 2 --timings` process (plus --lumis-args), whose
  second pass is timed (trace_s); the first is the warm-up. The rays in pixel order.
- lumis-8: the same with `--packets` (after --lumis-args) on the same rays reordered into
  Embree-8's 4 x 2 tiles (tile_order): each tile's pixels consecutively, lanes as in the
  packet, so that lumis's packets (each group of 8 consecutive rays, traced together where
  they share an origin and the direction signs, else one at a time) are Embree-8's packets.
  The full tiles come first, in Embree-8's order; where W % 4 == 0 and H % 2 == 0 (the
  default 512x384) that is every tile and every group is exactly one tile. At a ragged
  right or bottom edge the partly filled tiles follow, their valid pixels only, so their
  groups of 8 mix tiles: lumis answers them correctly but may walk them one ray at a time
  (Embree-8 masks their empty lanes instead). lumis-8's records are mapped back to pixel
  order before they are compared. How many groups share an origin and direction signs is
  printed.
Every Embree loop fills each ray and the hit's invalid ids from the float32 (N, 8) rays and
writes t, primID, geomID, u, v and Ng per ray, as lumis writes its hit rows, so the engines'
times cover the same work. The native engines share one scene (robust, as bench_embree's;
--no-robust drops the flag), committed once; its build time is printed. Process start-up,
loading and building are outside every timing.

Timing: --runs rounds; in each, every engine traces the rays twice and the second pass is
timed; the order of the engines rotates from round to round, so load from other processes on
a shared machine moves every engine rather than the ratios. Throughput is rays / median
seconds; "best" is of the fastest pass. "CPU share" is the median of CPU time over wall time
(of each timed pass; for lumis, of its whole process): below 100%, other processes ran on the
CPU and stretched the times, and "best" is the more telling figure. This process pins itself to one CPU (--cpu, default the
last allowed one) before Embree is loaded, so TBB (and the lumis processes, which inherit the
mask) stay on it; --no-pin leaves the mask alone.

Ratios of throughput: lumis and lumis-8 over each Embree loop, lumis-8 over lumis, the packets
over Embree-1 and Embree-1 over embreex-1 (median; best beside).

Checks (exit 1 when one fails): the packet engines' hits equal Embree-1's exactly (t, primID and
geomID of every ray); lumis agrees with Embree-1 on hit or miss for at least 99.99% of the rays
(the same-triangle and t agreement are printed beside it, as bench_embree prints them);
lumis-8's records, in pixel order, equal lumis's bit for bit (the whole row: t, primitive,
object, u, v, normal, kind; a NaN equals a NaN of the same bits), as `--packets` promises.

--instructions instead counts instructions per ray under callgrind (valgrind): rtcIntersect1
and rtcIntersect8 alone (--toggle-collect), in the loops above, as bench_instructions counts
Embree. valgrind has no AVX-512, so Embree runs its AVX2 kernels there.

Needs numpy, embreex, trimesh (for --subdivide), a C compiler (`$CC`, else cc, gcc or clang)
and the lumis binary (--lumis PATH, $LUMIS_BIN, or target/release/lumis as bench_embree finds
it; lumis-8 needs one with `hits --packets`). With the defaults on 2 cores a run takes about
3 s on the 69k-triangle bunny and 10 s on the 1.1M one without lumis-8, which adds its
process per round; --instructions about 15 s and 60 s.
"""

from __future__ import annotations

import os
import resource
import time

# As in bench_embree: no BLAS threads spinning on the other core.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import shlex  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from . import exitcodes  # noqa: E402
from . import lumis as lumis_run  # noqa: E402
from .bench_embree import (  # noqa: E402
    agreement,
    cpu_model,
    lumis_revision,
    package_version,
    pin,
    prepare_model,
    ray_sets,
    run_lumis,
)
from .bench_instructions import callgrind  # noqa: E402
from .embree import EmbreeScene  # noqa: E402
from .embree_native import RECORD, Helper, NativeEmbree, packet_lanes  # noqa: E402
from .sizes import wxh  # noqa: E402

ENGINES = ("embree-1", "embree-8", "embree-8c", "embreex-1", "lumis", "lumis-8")
PACKETS = ("embree-8", "embree-8c")
LUMIS_PACKETS = ["--packets"]  # lumis-8's flag, after --lumis-args
# Ratios of throughput printed: (numerator engine, denominator engine).
RATIOS = (("lumis", "embree-1"), ("lumis", "embree-8"), ("lumis", "embree-8c"),
          ("lumis-8", "embree-1"), ("lumis-8", "embree-8"), ("lumis-8", "embree-8c"),
          ("lumis-8", "lumis"), ("embree-8", "embree-1"), ("embree-8c", "embree-1"),
          ("embree-1", "embreex-1"))
MIN_HIT_MISS = 0.9999


def parse_args(argv=None):
    p = argparse.ArgumentParser(
        description="Single-thread Mrays/s of Embree's rtcIntersect8 (4x2 pixel packets), its "
        "rtcIntersect1 and lumis on the same camera rays; the ratios; the hits' agreement.",
        epilog="Method:\n" + "\n".join("  " + line for line in __doc__.splitlines()),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("model", type=Path,
                   help="model or scene: .m, .obj, .gltf, .glb, .toml or .scn (triangles only)")
    p.add_argument("--runs", type=int, default=5, help="interleaved rounds; default 5")
    p.add_argument("--camera", default="512x384", metavar="WxH",
                   help="camera ray grid, one ray per pixel; default 512x384 (196,608 rays)")
    p.add_argument("--subdivide", type=int, default=0, metavar="N",
                   help="Loop-subdivide the model N times (trimesh) first; default 0")
    p.add_argument("--lumis-args", default="", metavar="ARGS",
                   help="extra arguments for `lumis hits`")
    p.add_argument("--cpu", type=int, default=None,
                   help="CPU to pin every engine to; default the last one allowed")
    p.add_argument("--no-pin", action="store_true", help="do not pin")
    p.add_argument("--no-robust", action="store_true",
                   help="build the Embree scene without the robust flag")
    p.add_argument("--instructions", action="store_true",
                   help="count Embree's instructions per ray under callgrind instead of timing")
    p.add_argument("--json", type=Path, metavar="PATH",
                   help="also write every number measured as JSON")
    lumis_run.add_argument(p)
    args = p.parse_args(argv)
    if args.runs < 1:
        p.error("--runs must be at least 1")
    w, h = wxh(p, "--camera", args.camera, "512x384")
    args.camera_size = (w, h)
    if args.subdivide < 0:
        p.error("--subdivide must be >= 0")
    if not args.model.is_file():
        p.error(f"{args.model}: no such file")
    return args


def tile_order(width, height):
    """The pixel indices of a row-major `width` x `height` grid in the order lumis-8 traces
    them: the 4 x 2 tiles of `packet_lanes` (the Embree packets), each tile's pixels listed
    consecutively, lanes in packet order. The full tiles come first, in the packets' order, so
    each group of 8 consecutive rays from the start (lumis's packets: rays 8k to 8k + 7) is
    exactly one tile; the partly filled tiles of a ragged right or bottom edge (W not a
    multiple of 4, H not of 2) follow, their valid pixels only, so that there groups of 8 mix
    tiles. Where W % 4 == 0 and H % 2 == 0 every tile is full and the order is that of the
    packets. A permutation of range(width * height), int64."""
    lanes = packet_lanes(width, height)
    full = (lanes >= 0).all(axis=1)
    ragged = lanes[~full]
    return np.concatenate([lanes[full].ravel(), ragged[ragged >= 0]]).astype(np.int64)


def from_tile_order(rows, order):
    """`rows` traced in `order` (tile_order) back in pixel order: row i of the result is the
    row of pixel i."""
    out = np.empty_like(rows)
    out[order] = rows
    return out


def packet_groups(rays):
    """(groups, of which sharing an origin and direction signs): lumis's groups of 8
    consecutive `(N, 8)` rays (the last may be shorter) and how many of them have one origin
    (bit for bit) and, on each axis, one nonzero direction sign: the groups `lumis hits
    --packets` can walk together rather than one ray at a time (short groups of one ray
    are not counted as sharing)."""
    n = len(rays)
    groups = -(-n // 8)
    idx = np.minimum(np.arange(groups * 8), n - 1).reshape(groups, 8)  # as lumis pads
    bits = np.ascontiguousarray(rays, np.float32).view(np.uint32)[idx]
    dirs = np.ascontiguousarray(rays, np.float32)[idx][:, :, 3:6]
    same_origin = (bits[:, :, 0:3] == bits[:, :1, 0:3]).all(axis=(1, 2))
    sign = np.sign(dirs)
    same_sign = ((sign == sign[:, :1]) & (sign != 0)).all(axis=(1, 2))
    several = np.minimum(8, n - 8 * np.arange(groups)) > 1
    return groups, int((same_origin & same_sign & several).sum())


def same_rows(a, b):
    """Rows of lumis hit records `a` and `b` ((N, 9) float32) that differ in any column bit
    for bit (so NaN equals NaN of the same bits, -0 differs from 0), and per column the count
    of rays whose value differs."""
    a, b = np.ascontiguousarray(a, np.float32), np.ascontiguousarray(b, np.float32)
    if a.shape != b.shape:
        return {"rays": len(a), "rows_differ": max(len(a), len(b)), "columns_differ": [],
                "shapes": [list(a.shape), list(b.shape)]}
    diff = a.view(np.uint32) != b.view(np.uint32)
    return {"rays": len(a), "rows_differ": int(diff.any(axis=1).sum()),
            "columns_differ": [int(c) for c in diff.sum(axis=0)]}


def same_hits(a, b):
    """Counts of rays where the hit records `a` and `b` (embree_native.RECORD arrays) differ:
    in t (bit for bit, so inf equals inf and -0 differs from 0), in primID, in geomID."""
    return {
        "rays": len(a),
        "t_differs": int((a["t"].view(np.uint32) != b["t"].view(np.uint32)).sum()),
        "prim_differs": int((a["prim"] != b["prim"]).sum()),
        "geom_differs": int((a["geom"] != b["geom"]).sum()),
    }


def as_embreex(records):
    """Hit records in the keys of embreex's `run(..., output=True)`, for bench_embree's
    `agreement`."""
    return {"tfar": records["t"], "primID": records["prim"], "geomID": records["geom"]}


def rotated(seq, k):
    k %= len(seq)
    return list(seq[k:]) + list(seq[:k])


# Under callgrind: one pass of a native loop with only the Embree entry point counted.
CALLGRIND_SCRIPT = """
import sys, numpy as np
from pathlib import Path
from lumis_tools.embree_native import Helper, NativeEmbree
tris, rays, lanes = (np.load(sys.argv[i]) for i in (1, 2, 3))
embree = NativeEmbree(tris, Helper(Path(sys.argv[5])), robust=sys.argv[6] == "1")
embree.commit()
kind = sys.argv[4]
if kind == "1":
    embree.trace1(rays)
else:
    embree.trace8(rays, lanes, coherent=kind == "8c")
"""


def instructions(tris, rays, lanes, robust, tmp: Path):
    """Instructions per ray of rtcIntersect1 and rtcIntersect8 (both flags) under callgrind."""
    paths = [tmp / f"{n}.npy" for n in ("tris", "rays", "lanes")]
    for path, arr in zip(paths, (tris, rays, lanes), strict=True):
        np.save(path, arr)
    script = tmp / "callgrind_embree.py"
    script.write_text(CALLGRIND_SCRIPT)
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[1]))
    out = {}
    for kind, fn, engine in (("1", "rtcIntersect1", "embree-1"), ("8", "rtcIntersect8", "embree-8"),
                             ("8c", "rtcIntersect8", "embree-8c")):
        cmd = [sys.executable, str(script), *map(str, paths), kind, str(tmp), str(int(robust))]
        total = callgrind(cmd, tmp / f"cg.{kind}.out", [f"--toggle-collect={fn}"], env=env)
        out[engine] = total / len(rays)
        print(f"{engine}: {out[engine]:,.1f} instructions per ray ({fn})", flush=True)
    return out


def main(argv=None):
    args = parse_args(argv)
    lumis_extra = shlex.split(args.lumis_args)
    pinned = None if args.no_pin else pin(args.cpu)
    robust = not args.no_robust
    w, h = args.camera_size
    with tempfile.TemporaryDirectory(prefix="bench-embree8-") as tmp:
        tmp = Path(tmp)
        lumis_scene, tris, what = prepare_model(args.model, args.subdivide, tmp)
        print(f"model: {what}", flush=True)
        # Only the camera set is traced here; the other two are asked for with one ray each.
        rays = np.ascontiguousarray(ray_sets(tris, 1, 1, (w, h))["camera"], np.float32)
        lanes = packet_lanes(w, h)
        full = int((lanes >= 0).all(axis=1).sum())
        print(f"camera: {w}x{h} = {len(rays):,} rays in {len(lanes):,} packets of 4x2 pixels "
              f"({len(lanes) - full:,} partly filled)", flush=True)
        if args.instructions:
            counts = instructions(tris, rays, lanes, robust, tmp)
            if args.json:
                args.json.write_text(json.dumps({"model": what, "camera": [w, h],
                                                 "instructions_per_ray": counts}, indent=2))
            return exitcodes.OK
        return benchmark(args, tmp, lumis_scene, tris, what, rays, lanes, lumis_extra, pinned)


def benchmark(args, tmp, lumis_scene, tris, what, rays, lanes, lumis_extra, pinned):
    w, h = args.camera_size
    order = tile_order(w, h)
    tiled = np.ascontiguousarray(rays[order])
    groups, walkable = packet_groups(tiled)
    print(f"lumis-8: the rays in tile order, {groups:,} groups of 8 consecutive rays, "
          f"{walkable:,} with one origin and one direction sign per axis (the rest are traced "
          f"one ray at a time)", flush=True)
    lumis_run.use(args.lumis)
    exe = lumis_run.binary()
    rev = lumis_revision(args.lumis)
    robust = not args.no_robust
    embree = NativeEmbree(tris, Helper(tmp), robust=robust)
    build = embree.commit()
    version = embree.version()
    embreex = EmbreeScene(tris, robust=robust)
    embreex.commit()
    print(f"machine: {os.cpu_count()} CPUs ({cpu_model()}); "
          + (f"every engine pinned to CPU {pinned}" if pinned is not None else "not pinned"))
    print(f"Embree {version} (embreex {package_version('embreex')}'s library), "
          f"robust={robust}, native 8-wide packets: {bool(embree.property(33))}; commit "
          f"{build[0] * 1e3:.1f} ms (CPU {build[1] * 1e3:.1f} ms)")
    print(f"lumis: {exe} ({rev}), args: hits --threads 1 --repeat 2 "
          f"{' '.join(lumis_extra)}".rstrip() + "; lumis-8 adds " + " ".join(LUMIS_PACKETS))
    print(f"median of {args.runs} interleaved rounds", flush=True)

    def embreex_pass():
        wall, cpu = time.perf_counter(), time.thread_time()
        t, out = embreex.timed_intersect(rays)  # t: the query, without copying the rays in
        share = (time.thread_time() - cpu) / (time.perf_counter() - wall)
        rec = np.zeros(len(rays), RECORD)
        rec["t"], rec["prim"], rec["geom"] = out["tfar"], out["primID"], out["geomID"]
        rec["u"], rec["v"], rec["ng"] = out["u"], out["v"], out["Ng"]
        return t, share * t, rec

    def lumis_pass(packets=False):
        # lumis reports wall times; its share of the CPU is the process's CPU time (children's
        # rusage) over its wall time, loading and building included.
        wall, cpu = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
        if packets:  # the tile-ordered rays; the rows back in pixel order
            lh = run_lumis(lumis_scene, tiled, 2, lumis_extra + LUMIS_PACKETS)
            rows = from_tile_order(lh.rows, order)
        else:
            lh = run_lumis(lumis_scene, rays, 2, lumis_extra)
            rows = lh.rows
        wall, after = time.perf_counter() - wall, resource.getrusage(resource.RUSAGE_CHILDREN)
        used = after.ru_utime + after.ru_stime - cpu.ru_utime - cpu.ru_stime
        return lh.timings["trace_s"][1], used / wall, rows

    passes = {
        "embree-1": lambda: embree.trace1(rays),
        "embree-8": lambda: embree.trace8(rays, lanes),
        "embree-8c": lambda: embree.trace8(rays, lanes, coherent=True),
        "embreex-1": embreex_pass,
    }
    times = {e: [] for e in ENGINES}
    shares = {e: [] for e in ENGINES}  # CPU time / wall time: 1 when nothing else ran
    last = {}
    for round_no in range(args.runs):
        for engine in rotated(ENGINES, round_no):
            if engine in ("lumis", "lumis-8"):  # their --repeat 2 makes the warm-up pass
                t, share, last[engine] = lumis_pass(packets=engine == "lumis-8")
            else:
                passes[engine]()  # warm-up
                t, cpu, last[engine] = passes[engine]()
                share = cpu / t
            times[engine].append(t)
            shares[engine].append(share)
        print(f"round {round_no + 1}/{args.runs} done", flush=True)
    embree.close()

    n = len(rays)
    med = {e: statistics.median(times[e]) for e in ENGINES}
    best = {e: min(times[e]) for e in ENGINES}
    mrays = {e: n / med[e] / 1e6 for e in ENGINES}
    # Throughput of a over b: b's seconds over a's.
    ratios = {f"{a}/{b}": med[b] / med[a] for a, b in RATIOS}
    ratios_best = {f"{a}/{b}": best[b] / best[a] for a, b in RATIOS}
    checks = {e: same_hits(last[e], last["embree-1"]) for e in (*PACKETS, "embreex-1")}
    # embreex's t_max is 3e38 where the rays say inf (lumis_tools/embree.py): its misses'
    # t differs by design, so only its hits' t are compared.
    e1, ex = last["embree-1"], last["embreex-1"]
    hit = e1["geom"] != -1
    checks["embreex-1"]["t_differs"] = int((e1["t"][hit] != ex["t"][hit]).sum())
    lumis_agree = agreement(as_embreex(e1), last["lumis"])
    packets_same = same_rows(last["lumis-8"], last["lumis"])

    labels = {"embree-1": "Embree rtcIntersect1 (C loop)",
              "embree-8": "Embree rtcIntersect8, 4x2 packets",
              "embree-8c": "Embree rtcIntersect8, 4x2, COHERENT",
              "embreex-1": "Embree rtcIntersect1 (embreex loop)",
              "lumis": "lumis hits --threads 1",
              "lumis-8": "lumis hits --packets, 4x2 tile order"}
    print()
    share = {e: statistics.median(shares[e]) for e in ENGINES}
    print(f"{'engine':<10} {'':<37} {'Mrays/s':>8} {'(best)':>7} {'ns/ray':>7} {'CPU share':>9}")
    for e in ENGINES:
        print(f"{e:<10} {labels[e]:<37} {mrays[e]:>8.2f} {n / best[e] / 1e6:>7.2f} "
              f"{med[e] / n * 1e9:>7.1f} {share[e]:>9.0%}")
    if min(share.values()) < 0.9:
        print("(CPU share: CPU time over wall time of the timed passes, lumis's of its whole "
              "process; below 100% other processes ran on this CPU and stretched the times)")
    print()
    print("ratios of throughput (median; best):")
    for k, v in ratios.items():
        print(f"  {k:<20} {v:6.3f}  {ratios_best[k]:6.3f}")
    print("per-round seconds:")
    for e in ENGINES:
        print(f"  {e:<10} {' '.join(f'{t:.4f}' for t in times[e])}")
    print()
    failed = False
    for e, c in checks.items():
        bad = c["t_differs"] + c["prim_differs"] + c["geom_differs"]
        failed |= bad > 0 and e in PACKETS
        print(f"{e} vs embree-1: t differs on {c['t_differs']}, primID on "
              f"{c['prim_differs']}, geomID on {c['geom_differs']} of {c['rays']:,} rays"
              + ("" if bad == 0 or e not in PACKETS else "  FAILED"))
    ok = lumis_agree["same_hit_miss"] >= MIN_HIT_MISS
    failed |= not ok
    print(f"lumis vs embree-1: same hit/miss {lumis_agree['same_hit_miss']:.4%} (at least "
          f"{MIN_HIT_MISS:.2%}{'' if ok else ': FAILED'}), hit rate "
          f"{lumis_agree['hit_rate_embree']:.1%}; where both hit: same triangle "
          f"{lumis_agree['same_prim']:.4%}, t within 1e-4 {lumis_agree['t_within_1e-4']:.4%}")
    bad = packets_same["rows_differ"]
    failed |= bad > 0
    print(f"lumis-8 vs lumis (pixel order, whole rows bit for bit): {bad:,} of "
          f"{packets_same['rays']:,} rows differ"
          + ("" if bad == 0 else f" (per column {packets_same['columns_differ']})  FAILED"))

    if args.json:
        record = {
            "model": what, "lumis_scene": str(lumis_scene), "lumis_args": lumis_extra,
            "camera": list(args.camera_size), "rays": n, "packets": len(lanes),
            "runs": args.runs, "pinned_cpu": pinned, "robust": robust,
            "cpus": os.cpu_count(), "cpu_model": cpu_model(), "lumis_bin": str(exe),
            "lumis_rev": rev, "embree_version": version,
            "embree_commit_s": build, "seconds": times, "cpu_share": shares,
            "mrays_s": mrays, "ratios": ratios, "ratios_best": ratios_best,
            "same_as_embree_1": checks, "lumis_agreement": lumis_agree,
            "lumis_8": {"args": lumis_extra + LUMIS_PACKETS, "groups": groups,
                        "groups_one_origin_and_signs": walkable,
                        "same_as_lumis": packets_same},
            "failed": failed,
        }
        args.json.write_text(json.dumps(record, indent=2) + "\n")
    return exitcodes.FAILED if failed else exitcodes.OK


def cli():
    exitcodes.run(main, setup_errors=(OSError,))


if __name__ == "__main__":
    cli()
