#!/usr/bin/env python3
"""Times lumis against the paper's original C++ program on the Table I scenes, and measures how
far their images differ.

    .venv/bin/python tools/bench_original.py [--rounds 3] [--size 480x270] [--variants bsp,median]
        [--scenes line,lineFar] [--original-dir DIR] [--json out.json]

The original: every variant that ../shared/paper-original/build.sh makes (bsp, median, seg2,
seg4096, median_seg2, median_seg4096), built from its source tarball into a temporary folder
(about a minute on 2 cores), or taken from an earlier build with --original-dir. Each run is
`OMP_NUM_THREADS=T VARIANT SCENE.scn SPP 5 OUT.tga W H` from the scene folder (the original
opens model paths relative to its working directory).

lumis: `lumis render SCENE.scn -q -o OUT.png --width W --height H --threads T --display clamp
--stats-json S.json`. Its .scn loader already applies the original's defaults (1 sample per
axis, 5 lens rays, maxReflections 10, dispersion 5, clamp display, no contribution cutoff;
src/formats/scn/mod.rs), so only the size and threads are given; `--spp` only when --spp is not 1.
`--display clamp` is the loader's default for .scn too, and is written out because the image
comparison depends on it.

Timing: --rounds rounds; in each, every scene is rendered once by every chosen variant and by
lumis, in an order that rotates by one place per scene and per round, so no program always
runs first (after a cold cache) or right after the slowest one. Times are the wall clock of
each process (start-up, loading, building, rendering, writing: the same span for both
programs); lumis's render phase alone (`time.render_s` of --stats-json) is reported beside it.
Per scene: the original's fastest variant (the one with the least median over the rounds),
its median, lumis's median, and the ratio original/lumis. Total: the sum of the per-scene
fastest-original medians over the sum of the lumis medians. The targets (issue: >= 20x in
total, >= 5x on every scene) are checked against the wall-clock ratios and printed as met or
not; the exit code does not depend on them.

Images, from the last round: the original's TGA (24-bit, colour x 255 clamped, no transfer
curve) and lumis's clamp PNG. Printed: the mean absolute difference over all pixels and
channels in 8-bit levels, and the fraction of pixels where some channel differs by more than
8 levels, of lumis against --diff-variant (default bsp: the median variants drop an object from
two scenes, a defect of theirs); --json has them for every variant. The two programs do not
render the same image: depth of field is random in both (the original seeds by the clock) and
lumis does not copy the original's known defects (../shared/paper-original/README.md,
src/formats/scn/mod.rs), so the differences are reported, not judged.

The machine is printed beside the figures (lscpu model name, whether the CPU has avx2 and
avx512f). lumis is --lumis PATH or $LUMIS_BIN, else target/release/lumis of this checkout
(refused when older than src/, Cargo.toml or Cargo.lock). Needs numpy and Pillow.
One round of all 6 variants and 11 scenes at 480x270 took about 40 minutes on 2 shared cores
(ballsInAPit alone 18 minutes: median and median_seg4096 ran into the 300 s --timeout there, the
others took 2 minutes each), so --rounds 1 is the practical full run; use --variants or
--scenes for repeated rounds.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shlex
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

from . import exitcodes
from . import lumis as lumis_run
from . import paper
from .machine import cpu_info, cpu_summary
from .sizes import wxh

TARGET_TOTAL = 20.0
TARGET_EACH = 5.0
DIFF_LEVELS = 8
LUMIS = "lumis"  # the runner name lumis goes by beside the variants


def names_list(text: str, known: list[str], what: str) -> list[str]:
    """A comma-separated subset of `known`, kept in `known`'s order."""
    chosen = [x.strip() for x in text.split(",") if x.strip()]
    unknown = [x for x in chosen if x not in known]
    if unknown or not chosen:
        raise argparse.ArgumentTypeError(
            f"{what}: unknown {', '.join(unknown) or '(none given)'}; choose from "
            f"{', '.join(known)}")
    return [x for x in known if x in chosen]


def parse_args(argv=None):
    p = argparse.ArgumentParser(
        description="Wall-clock time of lumis against every variant of the paper's original "
        "program on the Table I scenes, interleaved over rounds, and the image difference.",
        epilog="Method:\n" + "\n".join("  " + line for line in __doc__.splitlines()),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--original-dir", type=Path, metavar="DIR",
                   help="an existing build.sh output folder (one executable per variant); "
                   "default: build every variant into a temporary folder")
    p.add_argument("--variants", default=",".join(paper.VARIANTS),
                   help=f"comma-separated variants of the original (default all: "
                   f"{','.join(paper.VARIANTS)})")
    p.add_argument("--scenes", default=",".join(paper.TABLE_I),
                   help="comma-separated Table I scene names (default all 11)")
    p.add_argument("--scene-dir", type=Path, default=paper.SCENES_DIR,
                   help="folder of the .scn files (default ../shared/paper-scenes/scenes)")
    p.add_argument("--rounds", type=int, default=3, help="interleaved rounds (default 3)")
    p.add_argument("--size", default="480x270", metavar="WxH", help="image size (default 480x270)")
    p.add_argument("--spp", type=int, default=1,
                   help="supersamples per axis, both programs (default 1, the paper's)")
    p.add_argument("--threads", type=int, default=2,
                   help="threads of both programs (OMP_NUM_THREADS, --threads; default 2)")
    p.add_argument("--timeout", type=float, default=300, metavar="S",
                   help="kill a run of the original after S seconds (default 300); that variant "
                   "is then skipped on that scene in later rounds and its median counts as "
                   "'> S', so it cannot be the fastest unless every variant timed out")
    p.add_argument("--diff-variant", default=None,
                   help="the variant whose image the printed difference is against (default "
                   "bsp when it runs, else the first chosen)")
    p.add_argument("--lumis-args", default="", metavar="ARGS",
                   help='extra arguments for `lumis render`, e.g. "--accel bsmp"')
    p.add_argument("--work", type=Path, metavar="DIR",
                   help="keep the renders (and the build) here; default a temporary folder "
                   "removed at the end")
    lumis_run.add_argument(p)
    p.add_argument("--json", type=Path, metavar="PATH",
                   help="also write every number measured as JSON")
    a = p.parse_args(argv)
    try:
        a.variants = names_list(a.variants, paper.VARIANTS, "--variants")
        a.scenes = names_list(a.scenes, paper.TABLE_I, "--scenes")
    except argparse.ArgumentTypeError as e:
        p.error(str(e))
    a.width, a.height = wxh(p, "--size", a.size, "480x270")
    if a.rounds < 1 or a.spp < 1 or a.threads < 1:
        p.error("--rounds, --spp and --threads must be at least 1")
    if a.diff_variant is None:
        a.diff_variant = "bsp" if "bsp" in a.variants else a.variants[0]
    elif a.diff_variant not in a.variants:
        p.error(f"--diff-variant {a.diff_variant} is not among --variants")
    return a


# ---------------------------------------------------------------------------------------------
# The two programs


def original_executables(a, work: Path) -> tuple[dict[str, Path], dict]:
    """{variant: executable} and what the build was (folder, BUILD_INFO.txt, seconds)."""
    if a.original_dir:
        folder = a.original_dir.resolve()
        build_s = None
    else:
        folder = work / "original"
        print(f"building the original into {folder} ...", flush=True)
        start = time.perf_counter()
        paper.build_original(folder)
        build_s = time.perf_counter() - start
    exes = {v: folder / v for v in a.variants}
    missing = [v for v, exe in exes.items() if not exe.is_file()]
    if missing:
        raise exitcodes.SetupError(f"{folder} has no {', '.join(missing)} (build.sh output "
                                   "folder?)")
    info = folder / "BUILD_INFO.txt"
    return exes, {"folder": str(folder), "build_s": build_s,
                  "build_info": info.read_text() if info.is_file() else None}


def lumis_command(exe: Path, scene: Path, png: Path, stats: Path, a) -> list[str]:
    cmd = [str(exe), "render", str(scene), "-q", "-o", str(png), "--width", str(a.width),
           "--height", str(a.height), "--threads", str(a.threads),
           # The .scn default already; the comparison with the original's TGA relies on it.
           "--display", "clamp", "--stats-json", str(stats)]
    if a.spp != 1:  # 1 is the .scn loader's default
        cmd += ["--spp", str(a.spp)]
    return cmd + shlex.split(a.lumis_args)


def run_lumis(exe: Path, scene: Path, png: Path, stats: Path, a) -> dict:
    """One lumis render: wall seconds of the process and its --stats-json summary."""
    cmd = lumis_command(exe, scene, png, stats, a)
    start = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed (exit {p.returncode}):\n{p.stderr}")
    summary = json.loads(stats.read_text())
    return {"wall_s": wall, "render_s": summary["time"]["render_s"],
            "load_s": summary["time"]["load_s"], "build_s": summary["time"]["build_s"],
            "rays": summary["rays"]["total"]}


def run_variant(exe: Path, scene: Path, tga: Path, a) -> dict:
    """One run of the original: wall seconds (None when it hit --timeout) and its ray count."""
    try:
        wall, stdout = paper.run_original(exe, scene, tga, width=a.width, height=a.height,
                                          spp=a.spp, threads=a.threads, scenes_dir=a.scene_dir,
                                          timeout=a.timeout)
    except subprocess.TimeoutExpired:
        tga.unlink(missing_ok=True)  # a partial image must not be compared
        return {"wall_s": None, "rays": None}
    return {"wall_s": wall, "rays": paper.rays_cast(stdout)}


def seconds(run: dict) -> float:
    """A run's wall seconds, a timed-out run's as infinity (slower than any finished one)."""
    return math.inf if run["wall_s"] is None else run["wall_s"]


def fmt_s(x: float, timeout: float) -> str:
    return f"> {timeout:g}" if math.isinf(x) else f"{x:.3f}"


def rotated(items: list, by: int) -> list:
    by %= len(items)
    return items[by:] + items[:by]


# ---------------------------------------------------------------------------------------------
# Measuring


def measure(a, exes: dict[str, Path], lumis_exe: Path, work: Path) -> dict:
    """{scene: {runner: [run dict per round]}}; the last round's images stay in `work`."""
    runners = a.variants + [LUMIS]
    runs = {s: {r: [] for r in runners} for s in a.scenes}
    start = time.perf_counter()
    for round_no in range(a.rounds):
        for scene_no, name in enumerate(a.scenes):
            scene = a.scene_dir / f"{name}.scn"
            # Rotating by round and scene: over the rounds each program runs in several
            # places of the order, so the load of the machine and the caches it meets are
            # shared out rather than always hitting the same one.
            order = rotated(runners, round_no + scene_no)
            line = []
            for runner in order:
                if runner == LUMIS:
                    r = run_lumis(lumis_exe, scene, work / f"{name}.lumis.png",
                                  work / f"{name}.lumis.json", a)
                    line.append(f"lumis {r['wall_s']:.2f}s (render {r['render_s']:.2f}s)")
                elif any(x["wall_s"] is None for x in runs[name][runner]):
                    # Timed out here before: it would again, and cost --timeout seconds.
                    r = {"wall_s": None, "rays": None, "skipped": True}
                    line.append(f"{runner} skipped")
                else:
                    r = run_variant(exes[runner], scene, work / f"{name}.{runner}.tga", a)
                    line.append(f"{runner} timeout ({a.timeout:g}s)" if r["wall_s"] is None
                                else f"{runner} {r['wall_s']:.2f}s")
                runs[name][runner].append(r)
            print(f"round {round_no + 1}/{a.rounds} {name}: {', '.join(line)} "
                  f"[{time.perf_counter() - start:.0f}s]", flush=True)
    return runs


def image_differences(a, work: Path) -> dict:
    """{scene: {variant: {"mean_abs": levels, "over": fraction}}}, lumis against each variant."""
    out = {}
    for name in a.scenes:
        ours = paper.load_rgb(work / f"{name}.lumis.png")
        out[name] = {}
        for v in a.variants:
            tga = work / f"{name}.{v}.tga"
            if not tga.is_file():  # timed out
                continue
            theirs = paper.load_rgb(tga)
            out[name][v] = {"mean_abs": paper.mean_abs_diff(theirs, ours),
                            "over": paper.fraction_over(theirs, ours, DIFF_LEVELS)}
    return out


def summarise(a, runs: dict, diffs: dict) -> dict:
    """Per scene: medians of every runner, the fastest variant, ratios; and the totals."""
    scenes = {}
    for name in a.scenes:
        medians = {v: statistics.median(seconds(r) for r in runs[name][v]) for v in a.variants}
        fastest = min(medians, key=medians.get)
        lumis_runs = runs[name][LUMIS]
        lumis_wall = statistics.median(r["wall_s"] for r in lumis_runs)
        lumis_render = statistics.median(r["render_s"] for r in lumis_runs)
        scenes[name] = {
            # JSON has no infinity: a variant that timed out has no median.
            "original_median_s": {v: None if math.isinf(m) else m for v, m in medians.items()},
            "fastest_variant": fastest,
            "fastest_s": medians[fastest],
            "lumis_wall_s": lumis_wall,
            "lumis_render_s": lumis_render,
            "ratio": medians[fastest] / lumis_wall,
            "ratio_render": medians[fastest] / lumis_render,
            "diff": diffs[name],
            "runs": runs[name],
        }
    orig_sum = sum(s["fastest_s"] for s in scenes.values())
    wall_sum = sum(s["lumis_wall_s"] for s in scenes.values())
    render_sum = sum(s["lumis_render_s"] for s in scenes.values())
    below = [n for n, s in scenes.items() if s["ratio"] < TARGET_EACH]
    total = {
        "original_fastest_sum_s": orig_sum,
        "lumis_wall_sum_s": wall_sum,
        "lumis_render_sum_s": render_sum,
        "ratio": orig_sum / wall_sum,
        "ratio_render": orig_sum / render_sum,
        "target_total": TARGET_TOTAL,
        "target_each": TARGET_EACH,
        "total_met": orig_sum / wall_sum >= TARGET_TOTAL,
        "scenes_below_each": below,
    }
    return {"scenes": scenes, "total": total}


# ---------------------------------------------------------------------------------------------
# Printing


def print_report(a, result: dict):
    scenes, total = result["scenes"], result["total"]
    dv = a.diff_variant
    print()
    print(f"{a.width}x{a.height}, {a.spp} sample(s) per axis, {paper.LENS_RAYS} lens rays, "
          f"{a.threads} threads; medians of {a.rounds} round(s), wall seconds per process")
    print(f"| scene | fastest original | s | lumis s | original/lumis | lumis render s "
          f"| original/render | mean abs diff vs {dv} | > {DIFF_LEVELS}/255 |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, s in scenes.items():
        d = s["diff"].get(dv, {"mean_abs": math.nan, "over": math.nan})
        print(f"| {name} | {s['fastest_variant']} | {fmt_s(s['fastest_s'], a.timeout)} | "
              f"{s['lumis_wall_s']:.3f} | {s['ratio']:.1f} | {s['lumis_render_s']:.3f} | "
              f"{s['ratio_render']:.1f} | {d['mean_abs']:.2f} | {d['over']:.1%} |")
    print(f"| **sum** | | {total['original_fastest_sum_s']:.2f} | "
          f"{total['lumis_wall_sum_s']:.2f} | **{total['ratio']:.1f}** | "
          f"{total['lumis_render_sum_s']:.2f} | {total['ratio_render']:.1f} | | |")

    print()
    print("original, median wall seconds of every variant:")
    print("| scene | " + " | ".join(a.variants) + " |")
    print("|---|" + "---:|" * len(a.variants))
    for name, s in scenes.items():
        cells = [fmt_s(math.inf if s["original_median_s"][v] is None
                       else s["original_median_s"][v], a.timeout) for v in a.variants]
        print(f"| {name} | " + " | ".join(cells) + " |")

    print()
    below = total["scenes_below_each"]
    print(f"target >= {TARGET_TOTAL:g}x in total: "
          f"{'met' if total['total_met'] else 'not met'} ({total['ratio']:.1f}x)")
    print(f"target >= {TARGET_EACH:g}x on every scene: "
          + ("met" if not below else
             f"not met on {len(below)} of {len(scenes)}: "
             + ", ".join(f"{n} {scenes[n]['ratio']:.1f}x" for n in below)))
    print(f"machine: {os.cpu_count()} CPUs, {cpu_summary()}")


def main(argv=None):
    a = parse_args(argv)
    try:
        import numpy  # noqa: F401
        import PIL  # noqa: F401
    except ImportError as e:
        raise exitcodes.SetupError(f"{e.name} is not installed (pip install numpy pillow)")
    a.scene_dir = a.scene_dir.resolve()
    for name in a.scenes:
        if not (a.scene_dir / f"{name}.scn").is_file():
            raise exitcodes.SetupError(f"{a.scene_dir / name}.scn is missing")
    lumis_run.use(a.lumis)
    lumis_exe = lumis_run.binary()
    print(f"machine: {os.cpu_count()} CPUs, {cpu_summary()}")
    print(f"lumis: {lumis_exe}, e.g. "
          + " ".join(lumis_command(lumis_exe, Path("SCENE.scn"), Path("OUT.png"),
                                   Path("S.json"), a)[1:]))

    with tempfile.TemporaryDirectory(prefix="bench-original-") as tmp:
        work = (a.work or Path(tmp)).resolve()
        work.mkdir(parents=True, exist_ok=True)
        exes, build = original_executables(a, work)
        print(f"original: {build['folder']} ({', '.join(a.variants)})"
              + (f", built in {build['build_s']:.0f}s" if build["build_s"] else "")
              + f"; OMP_NUM_THREADS={a.threads} VARIANT SCENE.scn {a.spp} {paper.LENS_RAYS} "
              f"OUT.tga {a.width} {a.height}, from {a.scene_dir}", flush=True)
        runs = measure(a, exes, lumis_exe, work)
        result = summarise(a, runs, image_differences(a, work))

    print_report(a, result)
    if a.json:
        record = {
            "size": [a.width, a.height], "spp": a.spp, "lens_rays": paper.LENS_RAYS,
            "threads": a.threads, "rounds": a.rounds, "variants": a.variants,
            "diff_variant": a.diff_variant, "diff_levels": DIFF_LEVELS,
            "lumis_bin": str(lumis_exe), "lumis_args": a.lumis_args,
            "cpus": os.cpu_count(), "cpu": cpu_info(), "original": build, **result,
        }
        a.json.write_text(json.dumps(record, indent=2) + "\n")


def cli():
    # RuntimeError: the original's build failed; ValueError: an unreadable image.
    exitcodes.run(main, setup_errors=(RuntimeError, OSError, ValueError))


if __name__ == "__main__":
    cli()
