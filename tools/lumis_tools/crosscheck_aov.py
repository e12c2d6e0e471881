#!/usr/bin/env python3
"""Cross-checks lumis's optional EXR layers (`--aov albedo,position,uv`) with OpenImageIO,
from the header's camera alone.

  crosscheck_aov.py [options] SCENE [SCENE ...]

Renders each scene with `lumis render SCENE -o X.exr --width 160 --height 90 --spp 1 --quiet
--aov albedo,position,uv`, reads it with OpenImageIO and checks:

  channels   the default channels plus exactly albedo.R/G/B, P.X/Y/Z, uv.U/V, all FLOAT.
  misses     (id.object = -1) P, albedo and uv are 0.
  P          on hits, P as a row vector times the worldToNDC M44f (OpenEXR/Imath convention),
             divided by w and scaled by the image size, lands on the pixel centre
             (x + 0.5, y + 0.5) within --pixel-tol (default 2e-3 pixel; far points are
             allowed float32's rounding of P, |P| x 2^-22, seen from the camera); and its
             camera-space depth (P times worldToCamera, z) is Z within 1e-5 relative.
  albedo     finite and >= 0 on hits.
  uv         finite on hits.

Exit status as every tool's (tools/README.md): 0 pass, 1 a check failed, 2 nothing could be
checked. --report writes JSON with every check and the worst errors."""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

import numpy as np

from . import exitcodes
from . import lumis as lumis_bin
from .exr_file import CHANNELS, Checks, matrix_attr, read_exr

AOV = ["albedo.R", "albedo.G", "albedo.B", "P.X", "P.Y", "P.Z", "uv.U", "uv.V"]


def check(exr, pixel_tol, checks):
    """Adds every check of the module doc for the render `exr` to `checks`; the worst errors."""
    names = sorted(exr.pixels)
    checks.add("channels", names == sorted(CHANNELS + AOV), f"{names}")
    if not all(n in exr.pixels for n in AOV + ["Z", "id.object"]):
        return {}
    for n in AOV:
        checks.add(f"{n} type", exr.formats[n] == "float", exr.formats[n])
    w2c = matrix_attr(exr.spec, "worldToCamera", checks)
    w2ndc = matrix_attr(exr.spec, "worldToNDC", checks)
    if w2c is None or w2ndc is None:
        return {}
    width, height = exr.size
    hit = exr.pixels["id.object"] >= 0
    p = np.stack([exr.pixels[n] for n in ("P.X", "P.Y", "P.Z")], axis=-1).astype(np.float64)
    aov = np.stack([exr.pixels[n] for n in AOV], axis=-1)
    checks.add("misses are 0", (aov[~hit] == 0).all(), f"{(~hit).sum()} misses")
    ph = np.concatenate([p[hit], np.ones((hit.sum(), 1))], axis=1)
    q = ph @ w2ndc  # row vectors: p' = p * M
    ys, xs = np.nonzero(hit)
    off = np.hypot(q[:, 0] / q[:, 3] * width - (xs + 0.5), q[:, 1] / q[:, 3] * height - (ys + 0.5))
    # float32 rounding of a far P moves it by |P| 2^-22 across the view: in pixels, that over
    # the depth times the focal length in pixels (the NDC scale).
    depth = (ph @ w2c)[:, 2]
    focal = abs(w2ndc[1, 1]) * height
    allowance = np.abs(p[hit]).max(axis=1, initial=0) * 2.0**-22 / np.maximum(depth, 1e-30) * focal
    worst_px = float(off.max(initial=0))
    checks.add("P reprojects onto the pixel centre", (off <= pixel_tol + allowance).all(),
               f"max {worst_px:.2e} px over {hit.sum()} hits (tolerance {pixel_tol})")
    z = exr.pixels["Z"][hit].astype(np.float64)
    rel = np.abs(depth - z) / np.maximum(np.abs(z), 1e-30)
    worst_z = float(rel.max(initial=0))
    checks.add("P depth is Z", (rel <= 1e-5).all(), f"max relative {worst_z:.2e}")
    albedo = aov[hit][:, 0:3]
    checks.add("albedo finite and >= 0", np.isfinite(albedo).all() and (albedo >= 0).all())
    checks.add("uv finite", np.isfinite(aov[hit][:, 6:8]).all())
    return {"hits": int(hit.sum()), "reprojection_px_max": worst_px, "z_rel_max": worst_z}


def main(argv=None):
    ap = argparse.ArgumentParser(prog="crosscheck_aov.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="+", metavar="SCENE")
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=90)
    ap.add_argument("--pixel-tol", type=float, default=2e-3)
    ap.add_argument("--report", metavar="JSON")
    ap.add_argument("--quiet", action="store_true", help="one line per scene")
    lumis_bin.add_argument(ap)
    args = ap.parse_args(argv)
    lumis_bin.use(args.lumis)
    code, results = exitcodes.OK, []
    with tempfile.TemporaryDirectory() as tmp:
        for scene in args.scenes:
            out = Path(tmp) / "aov.exr"
            lumis_bin.run(["render", scene, "-o", str(out), "--width", str(args.width),
                           "--height", str(args.height), "--spp", "1", "--quiet",
                           "--aov", "albedo,position,uv"])
            checks = Checks()
            stats = check(read_exr(out), args.pixel_tol, checks)
            failed = checks.code() != 0
            code = exitcodes.FAILED if failed else code
            results.append({"scene": scene, "ok": not failed, "stats": stats,
                            "checks": checks.items})
            print(f"{'FAIL' if failed else 'PASS':5} {scene}  {json.dumps(stats)}")
            for c in checks.items:
                if not c["ok"] or not args.quiet:
                    print(f"    {'ok  ' if c['ok'] else 'FAIL'} {c['check']}: {c['detail']}")
    if args.report:
        Path(args.report).parent.mkdir(parents=True, exist_ok=True)
        Path(args.report).write_text(json.dumps(results, indent=2) + "\n")
    return code


def cli():
    exitcodes.run(main, prog="crosscheck_aov")


if __name__ == "__main__":
    cli()
