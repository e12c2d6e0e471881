#!/usr/bin/env python3
"""Times lumis against Mitsuba 3 (scalar_rgb and llvm_ad_rgb) rendering the same lit bunny, and
checks that the three images agree.

    /work/venv-mitsuba/bin/python tools/bench_mitsuba.py [--size 1280x720] [--spp 4]
        [--rounds 3] [--threads 2] [--json out.json] [--keep DIR]
    /work/venv-mitsuba/bin/python tools/bench_mitsuba.py --size 160x90 --spp 8 --check-only

(any Python with tools/requirements-mitsuba.txt installed; see tools/README.md).

The scene, built from constants below so that both engines get it from one description:
- the Stanford bunny of the paper (../shared/paper-scenes/models/bunny.orig.m, 69,473
  triangles, or --model), flat-shaded: lumis reads .m files without normals and so shades them
  faceted, and Mitsuba is told `face_normals = true`;
- a 4 x 4 (bunny units) ground quad under it (two triangles), so the hard shadow is in the picture;
- one grey Lambert material (albedo 0.5) on both, lit from both sides (lumis shades the side the
  ray arrived on; Mitsuba's `diffuse` is one-sided, so it is wrapped in `twosided`);
- one point light, radiant intensity 1.2 W/sr, white;
- a pinhole camera with a 40 degree *vertical* field of view (lumis's `fov`; Mitsuba's
  `perspective` gets `fov_axis = "y"`, its default being x), black background.

Lighting model, from lumis's source (src/integrator/whitted.rs, src/light.rs, src/material.rs):
a hit's radiance is `Le + ambient * kd + sum over unshadowed lights of (kd / pi * cos) * E`
(plus Phong, mirror and refraction terms, all zero here), with `E = intensity / d^2` for a
point light (intensity is radiant intensity in W/sr, inverse-square falloff). That is exactly
what Mitsuba's `direct` integrator computes for a `diffuse` BSDF and a `point` emitter, whose
`intensity` is also radiant intensity, once lumis's ambient term (default 0.05) is set to 0 in
the TOML. Mitsuba's `direct` is given `emitter_samples = 1, bsdf_samples = 0`: a BSDF-sampled
ray can never hit a point light, so it would only cost time; with these settings both engines
trace one camera ray per sample and at most one shadow ray towards the light. (Mitsuba traces
its shadow ray inside `sample_emitter_direction`, before the BSDF is evaluated, so at every hit,
also where the surface faces away from the light; lumis casts one only where the unshadowed
contribution is non-zero. So Mitsuba traces somewhat more shadow rays than lumis reports.) No
secondary bounces exist in either (lumis's `max_depth` has nothing to reflect or refract).
So the exposure-matching scale printed beside the error should be 1 up to noise: it is a check
of the units, not a fudge.

Sampling: lumis's `--spp N` is N x N stratified, jittered samples per pixel averaged with equal
weights (a box filter over the pixel); Mitsuba gets the `stratified` sampler with N*N samples
(the same N x N jittered strata) and the `box` reconstruction filter (radius 0.5: each sample
counts in its own pixel only). The sample positions differ (different random streams), so the
images differ by noise at silhouettes and shadow edges; the scene's smooth parts agree exactly.
lumis also traces one more ray per pixel, through its centre, for the depth/normal/id layers
of its EXR (`rays.aov` in its stats, 1/(2 N^2 + 1) of its rays or less); Mitsuba writes RGB only.

Agreement: every Mitsuba image is scaled by the least-squares factor s that best matches it to
lumis's (s = sum(m l) / sum(m m) over all pixels and RGB channels), and the relative RMSE is
sqrt(mean((s m - l)^2)) / sqrt(mean(l^2)). Above --max-rmse (2%) the run fails with exit 1.
The scene is scaled up 10 times (--scene-scale; the light's intensity 100 times, so the
image is the same) because of Mitsuba's shadow rays: they leave a surface offset by about
1.8e-4 x (1 + largest |coordinate|) (its RayEpsilon), which at the bunny's own size (0.16
across) is a tenth of a percent of the model, a good fraction of a facet, and lets light
leak where the bunny touches the floor and at concave creases near the terminator. At scale
1 Mitsuba came out brighter than lumis at 45 such pixels of 1280x720 (error 0.68% against a
noise floor of 0.51%); at 10 and 100 the error is the noise floor (0.51%, 0.50%). lumis's
shadow rays leave by a bound on the rounding error of the hit point, far smaller, so its
image does not depend on the scale. Neither the workload nor the timings depend on it.
The remaining difference is sampling noise: the faceted bunny has an edge in nearly every
pixel. As a
yardstick lumis renders once more with --seed + 1 (untimed) and the same measure of lumis
against itself is printed as the noise floor; Mitsuba's error sits at that floor (measured
at 160x90: 11.3% against a floor of 11.5% at 1 x 1 spp, 1.38% / 1.46% at 4 x 4, 0.51% / 0.51%
at 8 x 8; at 1280x720, 4 x 4: 0.51% / 0.51%). The error falls as 1 / --spp (per axis), so a
quick check needs samples more than pixels: `--size 160x90 --spp 8 --check-only` (about
5 s; at --spp 1 the noise alone is over the 2% limit, and the run says so).

Timing: --rounds rounds; in each, the three engines run once each, in an order that rotates
from round to round (scalar, llvm, lumis; then llvm, lumis, scalar; ...), so load from other
processes on a shared machine spreads over all three rather than one. Each run is a fresh
process:
- Mitsuba: this script started again as a worker (`--worker VARIANT`), with HOME pointed at an
  empty temporary folder, so Dr.Jit's on-disk kernel cache (~/.drjit) starts empty and the
  first render pays the full trace-and-compile cost. It imports mitsuba, sets the variant and
  `dr.set_thread_count(--threads)` (Dr.Jit's nanothread pool, used by both variants' render
  loops), then times `mi.load_dict` (reading the PLY files, building the Embree BVH), a first
  render, and a second render of the same scene with the same seed (its kernel is in the
  in-memory cache by then). A render is `img = mi.render(scene, spp=N*N, seed=...);
  dr.eval(img); dr.sync_thread()`: Dr.Jit is lazy, so the time counts only once the image is
  actually computed.
  render-only = the second render; end-to-end = load + first render (the import of mitsuba
  and the setting of the variant, about a second of Python, are reported apart).
- lumis: `lumis render SCENE.toml -o out.exr --float --threads T --spp N --width W --height H
  --stats-json stats.json`. render-only = `time.render_s` of the stats (the tracing, after the
  scene is loaded and its BVH built; see src/cli/stats.rs); end-to-end = the process's wall time
  (start-up, parsing the .m text, building, rendering, writing the EXR).
Reported: medians over the rounds of each, the ratios lumis/scalar_rgb and lumis/llvm_ad_rgb
(below 1: lumis is faster), and the targets of the issue (lumis render-only <= 0.5x
scalar_rgb and <= 1.0x llvm_ad_rgb) as met or not; missing a target does not fail the run.
Each Mitsuba worker also reports the CPU time of its second render over its wall time, a check
that --threads was honoured. The CPU model and its SIMD flags are printed with the figures:
the LLVM variant compiles for the widest vector ISA the CPU has, so they matter.

Mitsuba's meshes are written by this script as binary PLY (Mitsuba's fastest loader) into a
temporary folder; the bunny is read with tools/lumis_tools/geometry.py and its vertices
re-indexed. lumis reads the .m file itself, as for the paper's scenes. --keep DIR keeps the
scene files and the images (lumis.exr, mitsuba_VARIANT.exr) there.

Requirements: tools/requirements-mitsuba.txt (mitsuba, its drjit, numpy, OpenImageIO). The
llvm_ad_rgb variant needs a shared libLLVM at run time, which the mitsuba wheel does not ship:
on Debian bookworm `apt-get install libllvm15` (Dr.Jit finds /usr/lib/x86_64-linux-gnu/
libLLVM-15.so.1 by itself; elsewhere point DRJIT_LIBLLVM_PATH at a libLLVM.so). Without it,
--variants scalar_rgb still runs. lumis is --lumis PATH or $LUMIS_BIN, else target/release/lumis
of this checkout (refused when older than src/, Cargo.toml or Cargo.lock).
A full run (1280x720, 16 spp, 3 rounds) takes about 100 s on 2 (busy) cores.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from . import TOOLS, exitcodes
from . import lumis as lumis_run
from .machine import cpu_info
from .mitsuba_scene import DEFAULT_SCALE, mitsuba_scene_dict, prepare_scene
from .rgb_images import agreement, read_exr_rgb, write_exr_rgb
from .sizes import wxh

DEFAULT_MODEL = lumis_run.REPO.parent / "shared" / "paper-scenes" / "models" / "bunny.orig.m"
VARIANTS = ("scalar_rgb", "llvm_ad_rgb")

# Targets of the issue, on render-only time: lumis / Mitsuba at most this.
TARGETS = {"scalar_rgb": 0.5, "llvm_ad_rgb": 1.0}


def parse_args(argv=None):
    p = argparse.ArgumentParser(
        description="Render time of lumis against Mitsuba 3 (scalar_rgb, llvm_ad_rgb) on the "
        "same point-lit bunny, with an image-agreement check (relative RMSE after exposure "
        "matching).",
        epilog="Method:\n" + "\n".join("  " + line for line in __doc__.splitlines()),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--model", type=Path, default=DEFAULT_MODEL,
                   help=".m mesh to render (default: the paper's bunny.orig.m)")
    p.add_argument("--size", default="1280x720", metavar="WxH",
                   help="image size; default 1280x720")
    p.add_argument("--spp", type=int, default=4,
                   help="samples per pixel PER AXIS as lumis counts them (4 = 16 samples); "
                   "default 4")
    p.add_argument("--rounds", type=int, default=3,
                   help="interleaved rounds, each running every engine once; default 3")
    p.add_argument("--threads", type=int, default=2, help="threads of every engine; default 2")
    p.add_argument("--variants", default=",".join(VARIANTS),
                   help=f"Mitsuba variants, comma-separated; default {','.join(VARIANTS)}")
    p.add_argument("--check-only", action="store_true",
                   help="one render per engine, compare the images, print no timings")
    p.add_argument("--max-rmse", type=float, default=0.02,
                   help="fail (exit 1) when a relative RMSE exceeds this; default 0.02")
    p.add_argument("--scene-scale", type=float, default=DEFAULT_SCALE, metavar="K",
                   help="scale the whole scene by K (light intensity by K^2, so the image stays "
                   f"the same); default {DEFAULT_SCALE:g} (see Agreement above)")
    p.add_argument("--seed", type=int, default=0, help="seed of both engines; default 0")
    p.add_argument("--keep", type=Path, metavar="DIR",
                   help="write the scene files and images here instead of a temporary folder")
    p.add_argument("--json", type=Path, metavar="PATH",
                   help="also write every number measured as JSON")
    lumis_run.add_argument(p)
    # Internal: one Mitsuba render in this process (see run_mitsuba).
    p.add_argument("--worker", metavar="VARIANT", help=argparse.SUPPRESS)
    p.add_argument("--scene-dir", type=Path, help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    w, h = wxh(p, "--size", args.size, "1280x720")
    args.width, args.height = w, h
    if args.spp < 1:
        p.error("--spp must be at least 1")
    if args.rounds < 1:
        p.error("--rounds must be at least 1")
    if args.threads < 1:
        p.error("--threads must be at least 1")
    args.variant_list = [v for v in args.variants.split(",") if v]
    for v in args.variant_list:
        if v not in VARIANTS:
            p.error(f"--variants: {v!r} is not one of {', '.join(VARIANTS)}")
    if args.worker is None and not args.model.is_file():
        p.error(f"{args.model}: no such file")
    return args


def worker(args):
    """One Mitsuba run in this process: prints its timings as one JSON line, saves the image
    of the second render as mitsuba_VARIANT.npy in the scene folder."""
    start = time.perf_counter()
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.worker)
    dr.set_thread_count(args.threads)
    import_s = time.perf_counter() - start

    def render(scene):
        wall, cpu = time.perf_counter(), time.process_time()
        img = mi.render(scene, spp=args.spp * args.spp, seed=args.seed)
        dr.eval(img)
        dr.sync_thread()
        return img, time.perf_counter() - wall, time.process_time() - cpu

    t = time.perf_counter()
    scene = mi.load_dict(mitsuba_scene_dict(mi, args.scene_dir, args.width, args.height,
                                            args.spp, args.scene_scale))
    load_s = time.perf_counter() - t
    _, first_s, _ = render(scene)
    img, second_s, second_cpu_s = render(scene)
    np.save(args.scene_dir / f"mitsuba_{args.worker}.npy", np.asarray(img, np.float32))
    print(json.dumps({"import_s": import_s, "load_s": load_s, "first_s": first_s,
                      "second_s": second_s, "second_cpu_s": second_cpu_s,
                      "threads": dr.thread_count(), "version": mi.__version__,
                      "drjit": dr.__version__}))


def run_mitsuba(args, variant, folder: Path):
    """Runs a worker process for `variant` with an empty Dr.Jit kernel cache; its timings."""
    home = Path(tempfile.mkdtemp(prefix="home-", dir=folder))
    env = dict(os.environ, HOME=str(home))
    # Through the script in tools/, which works whether or not the package is installed.
    cmd = [sys.executable, str(TOOLS / "bench_mitsuba.py"), "--worker", variant,
           "--scene-dir", str(folder), "--size", f"{args.width}x{args.height}",
           "--spp", str(args.spp), "--threads", str(args.threads), "--seed", str(args.seed),
           "--scene-scale", repr(args.scene_scale)]
    wall = time.perf_counter()
    p = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - wall
    if p.returncode != 0:
        raise RuntimeError(f"mitsuba {variant} failed (exit {p.returncode}):\n{p.stderr}")
    r = json.loads(p.stdout.strip().splitlines()[-1])
    r["process_s"] = wall
    r["render_s"] = r["second_s"]
    r["end_to_end_s"] = r["load_s"] + r["first_s"]
    return r


def run_lumis(args, folder: Path, seed=None, image="lumis.exr"):
    """One `lumis render` process; its timings from the stats JSON and the wall clock."""
    stats = folder / "lumis-stats.json"
    cmd = [str(lumis_run.binary()), "render", str(folder / "scene.toml"),
           "-o", str(folder / image), "--float", "--quiet",
           "--threads", str(args.threads), "--spp", str(args.spp),
           "--width", str(args.width), "--height", str(args.height),
           "--seed", str(args.seed if seed is None else seed), "--stats-json", str(stats)]
    wall, cpu = time.perf_counter(), children_cpu()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall, cpu = time.perf_counter() - wall, children_cpu() - cpu
    if p.returncode != 0:
        raise lumis_run.LumisError(f"lumis render failed (exit {p.returncode}): "
                                   f"{' '.join(cmd)}\n{p.stderr}")
    s = json.loads(stats.read_text())
    return {"render_s": s["time"]["render_s"], "end_to_end_s": wall,
            "load_s": s["time"]["load_s"], "build_s": s["time"]["build_s"],
            "write_s": s["time"]["write_s"], "process_cpu_s": cpu, "rays": s["rays"]}


def children_cpu():
    """User + system CPU seconds of the child processes waited for so far."""
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


# ---------------------------------------------------------------------------------------------


def median(xs):
    return statistics.median(xs)


def main(argv=None):
    args = parse_args(argv)
    if args.worker:
        worker(args)
        return exitcodes.OK
    lumis_run.use(args.lumis)
    exe = lumis_run.binary()
    cpu = cpu_info()
    model, simd = cpu["model"], [f for f, have in cpu["flags"].items() if have]
    print(f"machine: {os.cpu_count()} CPUs, {model}; SIMD flags: {' '.join(simd) or 'none'}")
    print(f"lumis: {exe}; threads {args.threads} for every engine; "
          f"{args.width}x{args.height}, {args.spp * args.spp} spp ({args.spp}x{args.spp})",
          flush=True)

    with tempfile.TemporaryDirectory(prefix="bench-mitsuba-") as tmp:
        folder = args.keep or Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        folder = folder.resolve()
        n_tris = prepare_scene(args.model, folder, args.scene_scale)
        print(f"scene: {args.model} ({n_tris:,} triangles, flat) + 2-triangle floor, one "
              f"point light; files in {folder}", flush=True)

        engines = [*args.variant_list, "lumis"]
        rounds = 1 if args.check_only else args.rounds
        times = {e: [] for e in engines}
        for r in range(rounds):
            # Rotate who goes first, so a slow spell on the shared machine does not always
            # fall on the same engine.
            order = engines[r % len(engines):] + engines[:r % len(engines)]
            for e in order:
                if e == "lumis":
                    times[e].append(run_lumis(args, folder))
                else:
                    times[e].append(run_mitsuba(args, e, folder))
            if not args.check_only:
                print(f"round {r + 1}/{rounds} done ({', '.join(order)})", flush=True)

        # The noise floor: lumis against itself with other sample positions. Mitsuba's
        # samples are as different from lumis's as these, so its error cannot go below this.
        run_lumis(args, folder, seed=args.seed + 1, image="lumis_seed2.exr")
        lumis_img = read_exr_rgb(folder / "lumis.exr")
        floor = agreement(read_exr_rgb(folder / "lumis_seed2.exr"), lumis_img)
        agree = {}
        for v in args.variant_list:
            img = np.load(folder / f"mitsuba_{v}.npy")
            if img.shape != lumis_img.shape:  # the images cannot agree: a failed check
                print(f"FAIL: mitsuba {v} image is {img.shape}, lumis's {lumis_img.shape}")
                return exitcodes.FAILED
            agree[v] = agreement(img, lumis_img)
            if args.keep:
                write_exr_rgb(folder / f"mitsuba_{v}.exr", img)

    mitsuba_version = times[args.variant_list[0]][0]["version"] if args.variant_list else "-"
    print()
    print(f"image agreement (Mitsuba {mitsuba_version} scaled onto lumis by least squares; "
          f"fail above {args.max_rmse:.1%}):")
    failed = False
    for v, a in agree.items():
        bad = a["rel_rmse"] > args.max_rmse
        failed |= bad
        print(f"  {v:<12} scale {a['scale']:.4f}, relative RMSE {a['rel_rmse']:.3%} "
              f"(unscaled {a['rel_rmse_unscaled']:.3%}) {'FAIL' if bad else 'ok'}")
    print(f"  noise floor: lumis --seed {args.seed + 1} against --seed {args.seed}: scale "
          f"{floor['scale']:.4f}, relative RMSE {floor['rel_rmse']:.3%}")
    if floor["rel_rmse"] > args.max_rmse:
        print(f"  (sampling noise alone exceeds {args.max_rmse:.1%} here: raise --spp)")

    result = {"size": [args.width, args.height], "spp": args.spp * args.spp,
              "threads": args.threads, "rounds": rounds, "cpu_model": model, "simd": simd,
              "cpus": os.cpu_count(), "lumis_bin": str(exe), "mitsuba": mitsuba_version,
              "agreement": agree, "noise_floor": floor, "runs": times}
    if not args.check_only:
        med = {e: {k: median(t[k] for t in times[e]) for k in ("render_s", "end_to_end_s")}
               for e in engines}
        result["median"] = med
        print()
        print(f"median of {rounds} rounds, seconds ({model}; {' '.join(simd)}):")
        print(f"  {'engine':<12} {'render-only':>12} {'end-to-end':>11}   details")
        for e in engines:
            ts = times[e]
            if e == "lumis":
                rays = ts[-1]["rays"]
                detail = (f"load {median(t['load_s'] for t in ts):.3f} + build "
                          f"{median(t['build_s'] for t in ts):.3f} s; {rays['total']:,} rays "
                          f"({rays['aov']:,} for AOVs); process CPU/wall "
                          f"{median(t['process_cpu_s'] / t['end_to_end_s'] for t in ts):.2f}")
            else:
                detail = (f"load {median(t['load_s'] for t in ts):.3f} + first render "
                          f"{median(t['first_s'] for t in ts):.3f} s; import "
                          f"{median(t['import_s'] for t in ts):.2f} s; render CPU/wall "
                          f"{median(t['second_cpu_s'] / t['second_s'] for t in ts):.2f}")
            print(f"  {e:<12} {med[e]['render_s']:>12.3f} {med[e]['end_to_end_s']:>11.3f}   "
                  f"{detail}")
        per_round = {e: " ".join(f"{t['render_s']:.3f}" for t in times[e]) for e in engines}
        print("  per round, render-only: "
              + "; ".join(f"{e} {line}" for e, line in per_round.items()))
        print()
        ratios = {}
        for v in args.variant_list:
            render = med["lumis"]["render_s"] / med[v]["render_s"]
            e2e = med["lumis"]["end_to_end_s"] / med[v]["end_to_end_s"]
            ratios[v] = {"render": render, "end_to_end": e2e}
            print(f"lumis/{v:<12} render-only {render:.3f}x, end-to-end {e2e:.3f}x; target "
                  f"render-only <= {TARGETS[v]}x: {'met' if render <= TARGETS[v] else 'NOT met'}")
        result["ratios"] = ratios

    if args.json:
        args.json.write_text(json.dumps(result, indent=2) + "\n")
    return exitcodes.FAILED if failed else exitcodes.OK


def cli():
    # RuntimeError: a Mitsuba worker failed (or Dr.Jit found no LLVM): nothing to compare.
    exitcodes.run(main, setup_errors=(RuntimeError, OSError))


if __name__ == "__main__":
    cli()
