#!/usr/bin/env python3
"""Cross-checks lumis's OpenEXR output: its layout and header, and its depth (Z), normal (N)
and id layers against an independent Embree oracle.

  crosscheck_exr.py [options] SCENE [SCENE ...]
  crosscheck_exr.py --compare A.exr B.exr [options]

SCENE mode renders each scene with `lumis render SCENE -o X.exr --width 160 --height 90
--spp 1 --quiet` (or checks the render given by --exr), reads it with OpenImageIO and checks
the contract of src/output/exr.rs:

  layout       one part, scanlines, ZIP compression (OIIO "zip": 16 lines), data window =
               display window = the requested size; channels exactly R G B A Z N.X N.Y N.Z
               id.prim id.object; Z, N.*, id.* FLOAT; R G B A HALF (FLOAT with --float).
  header       worldToCamera and worldToNDC (M44f); software = lumis/renderer = "lumis
               <version>"; lumis/spp (int) = spp^2; lumis/sppPerAxis (int) = spp;
               chromaticities = Rec.709/D65; lumis/renderSeconds absent or (float) >= 0.
  conventions  the matrices read as OpenEXR/Imath does (row vectors, p' = p * M): every
               pixel's worldToNDC ray passes through the worldToCamera eye, camera +z is the
               view direction, NDC (0,0) is the top-left and (1,1) the bottom-right corner,
               and points on each rebuilt ray project back onto the pixel centre.
  AOV values   misses (id.prim = -1): Z = +inf, N = 0, id.object = -1; hits: Z finite > 0,
               |N| = 1, integer ids >= 0, one object id per primitive; RGBA without NaN.

Then it rebuilds the pinhole ray through the centre of every pixel from the header alone
(eye from worldToCamera, direction from worldToNDC; no depth of field, as lumis fills the AOV
layers even when the scene has some), traces them with lumis_tools.oracle (Embree for
triangles, float64 for spheres) on geometry loaded without lumis (primitives matched to
lumis's then take its exact float32 coordinates, as in crosscheck_hits, so one-ulp differences
between the loaders' transforms stay out), and compares per pixel:

  id  lumis primitive ids map to oracle primitives by position (lumis_tools.idmap); the hit
      primitive must be the same, misses included. A differing pixel is classified:
        shared_edge     both hit triangles sharing an edge, at the same depth, and the ray
                        passes within the edge tolerance of it;
        edge            the same at other boundaries (shared vertex, T-junction, touching
                        primitives);
        silhouette      one side hit a triangle within the edge tolerance of its boundary,
                        the other missed it (and saw something behind, or nothing);
        grazing         the same for a sphere: the ray passes within tolerance of its rim;
        tie             two surfaces at the same depth away from any boundary (coincident or
                        duplicated geometry): either answer is right;
        retriangulated  the two loaders split a polygon into different triangles, and both
                        hits lie on it at the same depth (see lumis_tools.idmap);
        mismatch        none of these: a FAILURE;
        unmapped        lumis hit a primitive the independent loader does not have: FAILURE.
      The edge tolerance at a point p is --edge-tol * max(1, |p|_inf, ray length to p),
      default 2^-16. The legitimate classes are counted and reported, never failed.
  Z   where both saw the same surface (same primitive, or shared_edge/edge/tie/
      retriangulated): the relative error (Z_lumis - Z_oracle) / Z_oracle, Z_oracle being the
      camera-space depth (p - eye) . forward of the oracle's hit point.
      Defaults --fail Z=1e-4 --warn Z=1e-5.
  N   where both hit the same primitive: lumis's N minus the expected shading normal, per
      component (absolute). Expected: the sphere's outward normal; on triangles with vertex
      normals their interpolation with the oracle's barycentrics (u, v = weights of v1, v2),
      normalised and put on the winding side as lumis does; otherwise the winding normal
      cross(v1 - v0, v2 - v0). Never flipped towards the viewer (lumis does not flip it).
      Primitives under the .scn NormalMap are left out and counted (the report also says how
      many of them still show the unperturbed normal). Defaults --fail N=1e-3 --warn N=1e-4.

Ill-conditioned pixels: the rebuilt rays differ from lumis's float32 rays by a few ulps
(--ray-eps) and lumis's float32 hit points are a few ulps off their primitive, which moves
Z and N by an amount that grows as the incidence grazes (1/cos) and, for N, with the
curvature (1/r on small spheres, the spread of vertex normals on smooth meshes). Each pixel
gets that amount as an allowance. Pixels whose allowance is at most the warn threshold (nearly
all) go through OpenImageIO.ImageBufAlgo.compare with the plain thresholds; the others are
reported as ill-conditioned and held to warn + allowance and fail + allowance (so thresholds
far below float32 precision are effectively raised to it; --no-allowance turns this off). As
in idiff, a channel fails when more than --failpercent % of its compared pixels are over their
fail threshold (or any regular one over --hardfail), and warns likewise with --warn and
--warnpercent.

COMPARE mode (--compare A B) compares two EXRs channel by channel, matched by name, with
idiff's rules and defaults (--fail 1e-6 --warn 1e-6 --failrelative 0 --warnrelative 0
--failpercent 0 --warnpercent 0 --hardfail inf --hardwarn inf): a value fails when both its
absolute and its relative error (to the mean of the two) exceed the thresholds; equal values,
+inf included, match. --diff writes A - B.

Thresholds: --fail/--warn take VALUE (every channel) or CHANNEL=VALUE, repeatable. In SCENE
mode the channels are Z (relative) and N (absolute).

Status, the worst over all scenes: in the reports (JSON "status" and "code") idiff's levels,
pass 0, warn 1, fail 2, differ 3 (--compare: the images differ in size, parts or channel
names), error 4 (a file could not be read or written, a scene could not be rendered or
loaded). The exit status is the tools' scheme (tools/README.md): 0 pass; 1 warn, fail or
differ; 2 error or a wrong command line.

--report writes JSON: every check, per-channel statistics, class counts with examples,
timings. --diff writes an EXR; in SCENE mode (a directory when several scenes are given) with
Z.relerr, Z.allowance, N.X/N.Y/N.Z (lumis - expected), N.allowance, id.class (0 match,
1 shared_edge, 2 edge, 3 silhouette, 4 grazing, 5 tie, 6 retriangulated, 7 mismatch,
8 unmapped), oracle.Z, oracle.N.X/Y/Z, oracle.kind (-1 miss, 0 sphere, 1 triangle),
oracle.index.

Example (CI):  tools/crosscheck_exr.py scenes/*.toml assets/*.obj --report crosscheck.json
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

from . import exitcodes
from . import lumis as lumis_bin
from .exr_classify import CLASSES, LEGIT
from .exr_compare import compare_files, print_compare
from .exr_expect import POS_EPS_SPHERE, POS_EPS_TRIANGLE
from .exr_scene import check_scene
from .idiff import (EXIT_FILE, EXIT_OK, IDIFF_FAIL, IDIFF_WARN, SCENE_FAIL, SCENE_WARN, STATUS,
                    ToolError, UsageError, exit_status, parse_thresholds)


def _ill(c):
    if not c["ill_conditioned"]:
        return ""
    return (f" (+{c['ill_conditioned']} ill-conditioned, max {c['ill_conditioned_max_error']:.1e}"
            f" = {c['ill_conditioned_worst_over_warn']:.2f} of its warn threshold)")


def print_scene(r, verbose):
    ch = r.get("channels", {})
    line = f"{r['status'].upper():5} {r['scene']}"
    if ch:
        i, z, n = ch["id"], ch["Z"], ch["N"]
        legit = {c: i[c] for c in CLASSES if c in LEGIT and i[c]}
        line += (f"  id {i['match']}/{r['pixels']['total']} match"
                 + (f" {legit}" if legit else "")
                 + (f" mismatch {i['mismatch']}" if i["mismatch"] else "")
                 + (f" unmapped {i['unmapped']}" if i["unmapped"] else "")
                 + f" | Z rel max {z['maxerror']:.2e} over {z['compared']}"
                 + _ill(z)
                 + f" | N max {n['maxerror']:.2e} over {n['compared']}"
                 + _ill(n)
                 + (f" (normal-mapped left out: {n['normal_mapped_excluded']})"
                    if n["normal_mapped_excluded"] else ""))
    line += f"  [{r['timings'].get('total_s', 0):.2f}s]"
    print(line)
    for c in r["checks"]:
        if not c["ok"] or verbose:
            print(f"    {'ok  ' if c['ok'] else c['severity'].upper():5} {c['check']}: "
                  f"{c['detail']}")
    for name, c in ch.items():
        if not (c["code"] or verbose):
            continue
        brief = {k: v for k, v in c.items() if k != "examples"}
        print(f"    {name}: {json.dumps(_strict(brief))}")
        for cls_name, ex in c.get("examples", {}).items():
            if cls_name in LEGIT and not verbose:
                continue
            for e in ex[:3]:
                print(f"      {cls_name}: {json.dumps(_strict(e))}")


# ---------------------------------------------------------------------------------------------


def main(argv=None):
    ap = argparse.ArgumentParser(prog="crosscheck_exr.py", description=__doc__,
                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="*", metavar="SCENE",
                    help="scene files (.toml, .scn, .obj, .gltf, .glb) to render and check")
    ap.add_argument("--compare", nargs=2, metavar=("A", "B"),
                    help="compare two EXR files channel by channel instead")
    g = ap.add_argument_group("rendering (SCENE mode)")
    g.add_argument("--width", type=int, default=160, help="image width (default: %(default)s)")
    g.add_argument("--height", type=int, default=90, help="image height (default: %(default)s)")
    g.add_argument("--spp", type=int, default=1,
                   help="lumis --spp, N gives NxN samples (default: %(default)s)")
    g.add_argument("--float", action="store_true",
                   help="render with --float and expect FLOAT RGBA (else HALF)")
    g.add_argument("--render-arg", action="append", metavar="ARG",
                   help="extra argument for lumis render, e.g. --render-arg=--accel=bsp "
                        "(repeatable); nothing that changes the geometry (the oracle and the "
                        "id map load the scene as lumis does by default)")
    g.add_argument("--exr", metavar="PATH",
                   help="check this existing lumis render of the (single) SCENE instead of "
                        "rendering; its own size is expected and lumis/spp is not checked")
    g.add_argument("--keep-exr", metavar="DIR", help="keep the renders in DIR")
    g = ap.add_argument_group("thresholds (idiff-like)")
    g.add_argument("--fail", action="append", metavar="[CH=]VAL",
                   help="failure threshold; SCENE mode defaults Z=1e-4 (relative) N=1e-3 "
                        "(absolute); compare mode default 1e-6 (absolute)")
    g.add_argument("--warn", action="append", metavar="[CH=]VAL",
                   help="warning threshold; SCENE mode defaults Z=1e-5 N=1e-4; compare mode "
                        "default 1e-6")
    g.add_argument("--failpercent", type=float, default=0.0,
                   help="allow this percentage of compared pixels over the fail threshold "
                        "(default: 0)")
    g.add_argument("--warnpercent", type=float, default=0.0,
                   help="allow this percentage of compared pixels over the warn threshold "
                        "(default: 0)")
    g.add_argument("--hardfail", type=float, default=math.inf,
                   help="fail if any pixel's error exceeds this (default: inf)")
    g.add_argument("--hardwarn", type=float, default=math.inf,
                   help="warn if any pixel's error exceeds this (default: inf)")
    g.add_argument("--failrelative", type=float, default=0.0,
                   help="compare mode: a value fails only if its relative error (to the mean "
                        "of the two) also exceeds this (default: 0)")
    g.add_argument("--warnrelative", type=float, default=0.0,
                   help="compare mode: the same for warnings (default: 0)")
    g.add_argument("--edge-tol", type=float, default=2.0 ** -16,
                   help="relative distance to a primitive's boundary under which a differing "
                        "id is classified, not failed (default: 2^-16)")
    g.add_argument("--ray-eps", type=float, default=2.0 ** -22,
                   help="relative error assumed for the rebuilt camera rays (direction, and eye "
                        "position against its magnitude) against lumis's own float32 rays; "
                        "with the float32 error of hit points it decides each pixel's "
                        "allowance and so which pixels are ill-conditioned (default: 2^-22)")
    g.add_argument("--no-allowance", action="store_true",
                   help="hold every pixel to the plain thresholds: no allowance, no "
                        "ill-conditioned pixels (expect failures at grazing incidence)")
    g = ap.add_argument_group("output")
    g.add_argument("--diff", metavar="PATH",
                   help="write a difference EXR; with several scenes (or an existing "
                        "directory) PATH is a directory and each gets SCENE_NAME.diff.exr")
    g.add_argument("--report", metavar="PATH", help="write the JSON report here")
    g.add_argument("-q", "--quiet", action="store_true", help="print only failures")
    g.add_argument("-v", "--verbose", action="store_true", help="print every check")
    lumis_bin.add_argument(ap)
    args = ap.parse_args(argv)
    lumis_bin.use(args.lumis)

    if args.compare and args.scenes:
        ap.error("give either SCENE files or --compare A B, not both")
    if not args.compare and not args.scenes:
        ap.error("give SCENE files or --compare A B")
    if args.exr and len(args.scenes) != 1:
        ap.error("--exr checks the render of exactly one SCENE")

    results = []
    mode = "compare" if args.compare else "scene"
    try:
        fail_spec = parse_thresholds(args.fail, IDIFF_FAIL if args.compare else SCENE_FAIL, mode)
        warn_spec = parse_thresholds(args.warn, IDIFF_WARN if args.compare else SCENE_WARN, mode)
    except UsageError as e:
        ap.error(str(e))
    if args.compare:
        try:
            r = compare_files(args.compare[0], args.compare[1], args, fail_spec, warn_spec)
        except ToolError as e:
            r = {"a": args.compare[0], "b": args.compare[1], "channels": {},
                 "status": STATUS[EXIT_FILE], "code": EXIT_FILE, "error": str(e)}
        results.append(r)
        if not args.quiet or r["code"]:
            print_compare(r, args.verbose)
        code = r["code"]
    else:
        code = EXIT_OK
        for scene in args.scenes:
            diff_path = None
            if args.diff:
                many = len(args.scenes) > 1 or Path(args.diff).is_dir()
                diff_path = (Path(args.diff) / (Path(scene).name + ".diff.exr") if many
                             else Path(args.diff))
            try:
                r = check_scene(scene, args, fail_spec, warn_spec, diff_path)
            except ToolError as e:
                r = {"scene": scene, "status": STATUS[EXIT_FILE], "code": EXIT_FILE,
                     "error": str(e)}
                print(f"ERROR {scene}: {e}", file=sys.stderr)
            else:
                if not args.quiet or r["code"]:
                    print_scene(r, args.verbose)
            results.append(r)
            code = max(code, r["code"])
        if len(args.scenes) > 1 and not args.quiet:
            counts = {s: sum(r["status"] == s for r in results) for s in STATUS.values()}
            print("summary: " + ", ".join(f"{v} {k}" for k, v in counts.items() if v))
    if args.report:
        doc = {"tool": "crosscheck_exr", "status": STATUS[code], "code": code,
               "mode": "compare" if args.compare else "scene", "results": results}
        if args.compare:
            doc["thresholds"] = {"fail": fail_spec, "warn": warn_spec,
                                 "failrelative": args.failrelative,
                                 "warnrelative": args.warnrelative,
                                 "failpercent": args.failpercent,
                                 "warnpercent": args.warnpercent,
                                 "hardfail": args.hardfail, "hardwarn": args.hardwarn}
        else:
            doc["settings"] = {"width": args.width, "height": args.height, "spp": args.spp,
                               "float": args.float, "render_args": args.render_arg or [],
                               "lumis": str(lumis_bin.binary()) if not args.exr else None}
            doc["thresholds"] = {"fail": fail_spec[1], "warn": warn_spec[1],
                                 "failpercent": args.failpercent,
                                 "warnpercent": args.warnpercent,
                                 "hardfail": args.hardfail, "hardwarn": args.hardwarn,
                                 "edge_tol": args.edge_tol, "ray_eps": args.ray_eps,
                                 "no_allowance": args.no_allowance,
                                 "pos_eps_triangle": POS_EPS_TRIANGLE,
                                 "pos_eps_sphere": POS_EPS_SPHERE}
        Path(args.report).parent.mkdir(parents=True, exist_ok=True)
        Path(args.report).write_text(json.dumps(_strict(doc), indent=2, allow_nan=False,
                                                default=_json_default) + "\n")
    return exit_status(code)


def _strict(o):
    """Non-finite floats as the strings "inf", "-inf", "nan" (JSON has no such numbers)."""
    if isinstance(o, dict):
        return {k: _strict(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [_strict(v) for v in o]
    if isinstance(o, (float, np.floating)) and not math.isfinite(o):
        return str(float(o))
    return o


def _json_default(o):
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(type(o))


def cli():
    exitcodes.run(main, prog="crosscheck_exr")


if __name__ == "__main__":
    cli()
