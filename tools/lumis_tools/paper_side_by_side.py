#!/usr/bin/env python3
"""Renders the paper's Table I scenes with the original C++ program and with lumis at the same
settings, and reports the mean absolute difference per scene in 8-bit levels; writes one
side-by-side PNG per scene (original | lumis) for docs/paper.md.

Each scene is compared twice: as written (depth of field where the file or the original's
default asks for it, random in both programs) and as a pinhole variant (`dispersion -1`
appended, written to the work folder), which takes the lens noise out of the difference.

Usage:
  tools/paper_side_by_side.py ORIG_BUILD_DIR LUMIS_BIN [options]

ORIG_BUILD_DIR is the output folder of ../shared/paper-original/build.sh (it holds `bsp`);
LUMIS_BIN a lumis binary (e.g. target/release/lumis), run as it is. When either, the scene
folder, numpy or Pillow is missing the script says so and exits 2 (nothing was compared), the
status every tool gives for a missing input (tools/README.md). Needs numpy and Pillow.
"""
import argparse
import subprocess
import time
from pathlib import Path

from . import exitcodes
from .paper import (LENS_RAYS, REPO, SCENES_DIR, TABLE_I, load_rgb, mean_abs_diff,
                    run_original as render_original)


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("orig_dir", type=Path, help="build.sh output folder of the original")
    p.add_argument("lumis", type=Path, help="lumis binary")
    p.add_argument("--variant", default="bsp", help="which build of the original (default bsp)")
    p.add_argument("--scenes", type=Path, default=SCENES_DIR)
    p.add_argument("--work", type=Path, default=Path("/tmp/lumis-paper-side-by-side"),
                   help="renders and pinhole scene variants go here (default %(default)s)")
    p.add_argument("--out", type=Path, default=REPO / "docs/paper/side-by-side",
                   help="side-by-side PNGs (default docs/paper/side-by-side)")
    p.add_argument("--no-figures", action="store_true", help="only measure, write no PNGs")
    p.add_argument("--reuse-original", action="store_true",
                   help="keep the original's renders already in --work (its lens jitter is "
                        "seeded by the clock, so reusing them compares lumis builds fairly)")
    p.add_argument("--width", type=int, default=480)
    p.add_argument("--height", type=int, default=270)
    p.add_argument("--lens-rays", type=int, default=LENS_RAYS, help="the original's depth complexity")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--label", default="lumis", help="names this lumis run's renders in --work")
    p.add_argument("--orig-label", default="original",
                   help="names the original's renders in --work (e.g. for a patched build)")
    p.add_argument("--pinhole-only", action="store_true", help="skip the as-written renders")
    p.add_argument("--lumis-arg", action="append", default=[],
                   help="extra argument for `lumis render` (repeatable), e.g. --lumis-arg=--display=srgb")
    p.add_argument("--only", action="append", default=[], help="scene name (repeatable)")
    return p.parse_args(argv)


def skip(reason):
    print(f"skipping: {reason}")
    raise SystemExit(exitcodes.SETUP)  # nothing was compared


def pinhole_variant(scene: Path, work: Path) -> Path:
    """The scene with `dispersion -1` appended: the last statement wins in both programs."""
    out = work / "pinhole" / scene.name
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(scene.read_text() + "\ndispersion -1\n")
    return out


def run_original(exe: Path, scene: Path, out_tga: Path, a) -> float:
    seconds, _ = render_original(exe, scene, out_tga, width=a.width, height=a.height,
                                 lens_rays=a.lens_rays, threads=a.threads, scenes_dir=a.scenes)
    return seconds


def run_lumis(exe: Path, scene: Path, out_png: Path, a) -> float:
    t = time.monotonic()
    subprocess.run([str(exe), "render", str(scene), "-q", "--width", str(a.width), "--height",
                    str(a.height), "--threads", str(a.threads), "-o", str(out_png)]
                   + a.lumis_arg, check=True)
    return time.monotonic() - t


def side_by_side(orig, ours, path: Path):
    import numpy as np
    from PIL import Image

    path.parent.mkdir(parents=True, exist_ok=True)
    img = Image.fromarray(np.concatenate([orig, ours], axis=1).astype(np.uint8), "RGB")
    img.save(path, optimize=True)


def main(argv=None):
    a = parse_args(argv)
    exe = a.orig_dir / a.variant
    if not exe.is_file():
        skip(f"no original build at {exe} (see ../shared/paper-original/README.md)")
    if not a.lumis.is_file():
        skip(f"no lumis binary at {a.lumis} (cargo build --release)")
    if not a.scenes.is_dir():
        skip(f"no paper scenes at {a.scenes}")
    try:
        import numpy  # noqa: F401
        import PIL  # noqa: F401
    except ImportError as e:
        skip(f"{e.name} is not installed (pip install numpy pillow)")
    a.scenes = a.scenes.resolve()
    a.work.mkdir(parents=True, exist_ok=True)
    names = a.only or TABLE_I
    rows = []
    for name in names:
        scene = a.scenes / f"{name}.scn"
        if not scene.is_file():
            skip(f"{scene} is missing")
        row = {"scene": name}
        kinds = [("dof", scene), ("pinhole", pinhole_variant(scene, a.work))]
        for kind, src in kinds[1:] if a.pinhole_only else kinds:
            tga = a.work / a.orig_label / f"{name}.{kind}.tga"
            png = a.work / a.label / f"{name}.{kind}.png"
            tga.parent.mkdir(parents=True, exist_ok=True)
            png.parent.mkdir(parents=True, exist_ok=True)
            if not (a.reuse_original and tga.is_file()):
                row[f"orig_s_{kind}"] = run_original(exe, src.resolve(), tga.resolve(), a)
            row[f"lumis_s_{kind}"] = run_lumis(a.lumis, src, png, a)
            orig, ours = load_rgb(tga), load_rgb(png)
            row[kind] = mean_abs_diff(orig, ours)
            if kind == "dof" and not a.no_figures:
                side_by_side(orig, ours, a.out / f"{name}.png")
        rows.append(row)
        print(f"{name}: as written {row.get('dof', float('nan')):.2f}, "
              f"pinhole {row['pinhole']:.2f}", flush=True)
    print()
    print(f"| scene | as written | pinhole |  ({a.orig_label} vs {a.label})")
    print("|---|---:|---:|")
    for r in rows + [mean_row(rows)]:
        print(f"| {r['scene']} | {r.get('dof', float('nan')):.2f} | {r['pinhole']:.2f} |")


def mean_row(rows):
    """The mean over scenes of each difference column."""
    out = {"scene": "**mean**"}
    for k in ("dof", "pinhole"):
        if all(k in r for r in rows):
            out[k] = sum(r[k] for r in rows) / len(rows)
    return out


def cli():
    # CalledProcessError: lumis failed on a scene; RuntimeError: the original did.
    exitcodes.run(main, setup_errors=(subprocess.CalledProcessError, RuntimeError, OSError))


if __name__ == "__main__":
    cli()
