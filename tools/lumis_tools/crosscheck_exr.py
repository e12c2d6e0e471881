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
               <version>"; lumis/spp (int) = spp^2; lumis/renderSeconds (float) >= 0.
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
import warnings
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

from . import exitcodes
from . import lumis as lumis_bin
from .prims import LumisPrims, Prims

EXIT_OK, EXIT_WARN, EXIT_FAIL, EXIT_SIZE, EXIT_FILE = 0, 1, 2, 3, 4
STATUS = {EXIT_OK: "pass", EXIT_WARN: "warn", EXIT_FAIL: "fail", EXIT_SIZE: "differ",
          EXIT_FILE: "error"}

CHANNELS = ["R", "G", "B", "A", "Z", "N.X", "N.Y", "N.Z", "id.prim", "id.object"]
FLOAT_CHANNELS = ["Z", "N.X", "N.Y", "N.Z", "id.prim", "id.object"]
RGBA = ["R", "G", "B", "A"]

# Scene mode defaults: Z relative error, N absolute error per component.
SCENE_FAIL = {"Z": 1e-4, "N": 1e-3}
SCENE_WARN = {"Z": 1e-5, "N": 1e-4}
# idiff's defaults.
IDIFF_FAIL = 1e-6
IDIFF_WARN = 1e-6
# Stands in for an infinite or NaN difference, which ImageBufAlgo.compare miscounts.
BIG = 1e30
# Relative error of lumis's float32 hit points against the coordinates they are computed from:
# triangle points interpolated from the corners (lumis's own bound gamma(7) ~ 7 ulps ~ 2^-21.2
# of the largest corner coordinate), sphere points projected in float64 then rounded, with Z
# computed from them in float32 (a few ulps of the point).
POS_EPS_TRIANGLE = 2.0 ** -21
POS_EPS_SPHERE = 2.0 ** -22

CLASSES = ["match", "shared_edge", "edge", "silhouette", "grazing", "tie", "retriangulated",
           "mismatch", "unmapped"]
LEGIT = {"shared_edge", "edge", "silhouette", "grazing", "tie", "retriangulated"}
SAME_DEPTH = {"shared_edge", "edge", "tie", "retriangulated"}


class ToolError(exitcodes.SetupError):
    """A file could not be read or written, or lumis failed: level "error" (exit status 2)."""


class UsageError(exitcodes.SetupError):
    """Bad command line (exit status 2)."""


def exit_status(level):
    """The process exit status of a report level: pass 0; warn, fail and differ 1 (a check
    did not pass: idiff too exits non-zero on warnings); error 2 (nothing could be checked)."""
    if level == EXIT_OK:
        return exitcodes.OK
    return exitcodes.SETUP if level == EXIT_FILE else exitcodes.FAILED


# ---------------------------------------------------------------------------------------------
# Thresholds


def parse_thresholds(values, defaults, mode):
    """`VALUE` or `CHANNEL=VALUE` items over `defaults` (a dict, or a float for all channels).
    Returns (default for unnamed channels, {channel: value})."""
    base = defaults if isinstance(defaults, float) else None
    per = {} if isinstance(defaults, float) else dict(defaults)
    for item in values or []:
        name, sep, val = item.rpartition("=")
        try:
            v = float(val)
        except ValueError:
            raise UsageError(f"bad threshold {item!r}: want VALUE or CHANNEL=VALUE") from None
        if not sep:
            if mode == "scene":
                per = {k: v for k in per}
            else:
                base, per = v, {}
        else:
            if mode == "scene" and name not in SCENE_FAIL:
                raise UsageError(f"threshold channel {name!r}: scene mode knows Z and N")
            per[name] = v
    return base, per


def threshold_for(channel, spec):
    base, per = spec
    return per.get(channel, base)


def verdict(res, npels, fail, warn, failpercent, warnpercent, hardfail, hardwarn):
    """idiff's decision for one CompareResults over `npels` compared pixels."""
    if res.nfail > failpercent / 100.0 * npels or res.maxerror > hardfail:
        return EXIT_FAIL
    if res.nwarn > warnpercent / 100.0 * npels or res.maxerror > hardwarn:
        return EXIT_WARN
    return EXIT_OK


def to_buf(arr):
    """An OIIO float ImageBuf of an (H, W) or (H, W, C) array."""
    arr = np.ascontiguousarray(arr, np.float32)
    if arr.ndim == 2:
        arr = arr[:, :, None]
    h, w, c = arr.shape
    buf = oiio.ImageBuf(oiio.ImageSpec(w, h, c, oiio.FLOAT))
    buf.set_pixels(oiio.ROI(0, w, 0, h, 0, 1, 0, c), arr)
    return buf


def _check_compare(res):
    """CompareResults.error is also set when pixels fail; only a message means it broke."""
    msg = oiio.geterror()
    if res.error and msg:
        raise ToolError(f"ImageBufAlgo.compare failed: {msg}")


def compare_stats(a, b, fail, warn, npels, args, failrel=0.0, warnrel=0.0):
    """ImageBufAlgo.compare of two arrays (same shape) plus idiff's verdict."""
    res = oiio.ImageBufAlgo.compare(to_buf(a), to_buf(b), fail, warn, failrel, warnrel)
    _check_compare(res)
    npels = max(npels, 1)
    total = a.shape[0] * a.shape[1] * (a.shape[2] if a.ndim == 3 else 1)
    ncomp = npels * (a.shape[2] if a.ndim == 3 else 1)
    status = verdict(res, npels, fail, warn, args.failpercent, args.warnpercent,
                     args.hardfail, args.hardwarn)
    return {
        "status": STATUS[status], "code": status,
        "fail": fail, "warn": warn,
        "nfail": int(res.nfail), "nwarn": int(res.nwarn),
        "maxerror": float(res.maxerror),
        "max_at": [int(res.maxx), int(res.maxy)] if res.maxerror else None,
        # compare averages over every pixel; rescaled to the compared ones.
        "meanerror": float(res.meanerror) * total / max(ncomp, 1),
        "rms_error": float(res.rms_error) * math.sqrt(total / max(ncomp, 1)),
        "PSNR": float(res.PSNR),
    }


# ---------------------------------------------------------------------------------------------
# Reading EXRs


@dataclass
class Exr:
    path: Path
    spec: oiio.ImageSpec
    nsubimages: int
    pixels: dict  # channel name -> (H, W) float32
    formats: dict  # channel name -> type name

    @property
    def size(self):
        return self.spec.width, self.spec.height


def read_exr(path):
    buf = oiio.ImageBuf(str(path))
    if not buf.init_spec(str(path), 0, 0) or buf.has_error:
        raise ToolError(f"cannot read {path}: {buf.geterror().splitlines()[0]}")
    spec = buf.spec()
    data = buf.get_pixels(oiio.FLOAT)
    if data is None or buf.has_error:
        raise ToolError(f"cannot read the pixels of {path}: {buf.geterror()}")
    data = np.asarray(data, np.float32).reshape(spec.height, spec.width, spec.nchannels)
    names = list(spec.channelnames)
    pixels = {n: data[:, :, i] for i, n in enumerate(names)}
    formats = {n: str(spec.channelformat(i)) for i, n in enumerate(names)}
    return Exr(Path(path), spec, buf.nsubimages, pixels, formats)


def attribute(spec, name):
    for a in spec.extra_attribs:
        if a.name == name:
            return a
    return None


# ---------------------------------------------------------------------------------------------
# Checks bookkeeping


@dataclass
class Checks:
    items: list = field(default_factory=list)

    def add(self, name, ok, detail="", severity=EXIT_FAIL):
        self.items.append({"check": name, "ok": bool(ok), "detail": detail,
                           "severity": STATUS[severity] if not ok else "pass"})
        return ok

    def code(self):
        worst = EXIT_OK
        for c in self.items:
            if not c["ok"]:
                worst = max(worst, {"fail": EXIT_FAIL, "warn": EXIT_WARN}[c["severity"]])
        return worst


def check_layout(exr, width, height, float_rgba, checks):
    s = exr.spec
    checks.add("single part", exr.nsubimages == 1, f"{exr.nsubimages} parts")
    checks.add("scanlines", s.tile_width == 0, f"tile width {s.tile_width}")
    comp = s.get_string_attribute("compression")
    checks.add("ZIP compression", comp == "zip", f"compression {comp!r}")
    window = (s.x, s.y, s.width, s.height, s.full_x, s.full_y, s.full_width, s.full_height)
    checks.add("data window = display window = requested size",
               window == (0, 0, width, height, 0, 0, width, height), f"{window}")
    names = list(s.channelnames)
    checks.add("channel names", sorted(names) == sorted(CHANNELS), f"{names}")
    want_rgba = "float" if float_rgba else "half"
    for n in names:
        want = want_rgba if n in RGBA else "float" if n in FLOAT_CHANNELS else None
        if want:
            checks.add(f"{n} type", exr.formats[n] == want, f"{exr.formats[n]}, want {want}")
    return all(n in exr.pixels for n in CHANNELS)


def matrix_attr(spec, name, checks):
    a = attribute(spec, name)
    if not checks.add(f"{name} attribute", a is not None and a.type == oiio.TypeMatrix,
                      "missing" if a is None else f"type {a.type}"):
        return None
    m = np.array(a.value, np.float64).reshape(4, 4)
    checks.add(f"{name} finite", np.isfinite(m).all(), f"{m.tolist()}")
    return m


def check_header(spec, spp, checks):
    w2c = matrix_attr(spec, "worldToCamera", checks)
    w2ndc = matrix_attr(spec, "worldToNDC", checks)
    sw = spec.get_string_attribute("software")
    checks.add("software = lumis <version>", sw.startswith("lumis "), repr(sw))
    rend = attribute(spec, "lumis/renderer")
    checks.add("lumis/renderer = software", rend is not None and rend.value == sw,
               repr(rend.value if rend is not None else None))
    a = attribute(spec, "lumis/spp")
    ok = a is not None and a.type == oiio.TypeInt and (spp is None or a.value == spp * spp)
    checks.add("lumis/spp (int, spp^2)", ok,
               f"{a.value if a is not None else None} ({a.type if a is not None else 'missing'}), "
            f"spp {spp}")
    a = attribute(spec, "lumis/renderSeconds")
    checks.add("lumis/renderSeconds (float >= 0)",
               a is not None and a.type == oiio.TypeFloat and a.value >= 0,
               f"{a.value if a is not None else None}")
    return w2c, w2ndc


# ---------------------------------------------------------------------------------------------
# Camera rays from the header


@dataclass
class CameraRays:
    eye: np.ndarray  # (3,)
    forward: np.ndarray  # (3,) unit, camera +z in world space
    rays: np.ndarray  # (H*W, 8) float32 as traced


def camera_rays(w2c, w2ndc, width, height, checks):
    """The pinhole ray through every pixel centre, from the Imath (row-vector) matrices.

    The eye is the camera-space origin mapped back to world space. A pixel's ray is the line of
    world points whose NDC x and y (after the homogeneous divide) are the pixel centre's: with
    p_h = (p, 1), x = (p_h . M[:, 0]) / (p_h . M[:, 3]), so p lies on the two planes
    p_h . (M[:, 0] - x M[:, 3]) = 0 and p_h . (M[:, 1] - y M[:, 3]) = 0, and the ray runs along
    their intersection. Only the x and y columns of worldToNDC are used, whatever its z."""
    c2w = np.linalg.inv(w2c)  # row-vector form: p_world = p_cam * c2w
    eye = c2w[3, :3] / c2w[3, 3]
    forward = c2w[2, :3] / np.linalg.norm(c2w[2, :3])
    right = c2w[0, :3] / np.linalg.norm(c2w[0, :3])
    up = c2w[1, :3] / np.linalg.norm(c2w[1, :3])
    xs = (np.arange(width) + 0.5) / width
    ys = (np.arange(height) + 0.5) / height
    nx, ny = np.meshgrid(xs, ys)  # (H, W)
    plane_x = w2ndc[None, None, :, 0] - nx[..., None] * w2ndc[None, None, :, 3]
    plane_y = w2ndc[None, None, :, 1] - ny[..., None] * w2ndc[None, None, :, 3]
    d = np.cross(plane_x[..., :3], plane_y[..., :3])
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    d *= np.sign(d @ forward)[..., None]

    # Conventions, checked on the numbers written.
    eye_h = np.append(eye, 1.0)
    scale = np.abs(w2ndc).max() * max(1.0, np.abs(eye).max())
    resid = max(np.abs(plane_x @ eye_h).max(), np.abs(plane_y @ eye_h).max()) / scale
    checks.add("every pixel ray passes through the worldToCamera eye", resid < 1e-5,
               f"max relative residual {resid:.2e}")
    ahead = np.append(eye + forward, 1.0) @ w2c
    checks.add("worldToCamera: +z is the view direction", abs(ahead[2] - 1) < 1e-4
               and abs(ahead[0]) < 1e-4 and abs(ahead[1]) < 1e-4, f"{ahead[:3]}")
    cam = (d @ np.stack([right, up, forward]).T)  # camera-space directions
    tl, br = cam[0, 0], cam[-1, -1]
    checks.add("worldToNDC: (0,0) is the top-left corner",
               tl[0] < 0 < tl[1] and br[1] < 0 < br[0],
               f"top-left camera dir {tl.round(4)}, bottom-right {br.round(4)}")
    # Round trip: a point along each ray projects back onto its pixel centre.
    p = eye + max(3.0, float(np.abs(eye).max())) * d
    q = np.concatenate([p, np.ones(p.shape[:2] + (1,))], axis=-1) @ w2ndc
    err = max(np.abs(q[..., 0] / q[..., 3] * width - (nx * width)).max(),
              np.abs(q[..., 1] / q[..., 3] * height - (ny * height)).max())
    checks.add("worldToNDC round trip to pixel centres", err < 1e-3, f"max {err:.2e} px")

    rays = np.zeros((height * width, 8), np.float32)
    rays[:, 0:3] = eye
    rays[:, 3:6] = d.reshape(-1, 3)
    rays[:, 7] = np.inf
    return CameraRays(eye, forward, rays)


# ---------------------------------------------------------------------------------------------
# Geometry probes for classifying id differences (float64, a handful of pixels)


def _seg_dist(p, a, b):
    ab = b - a
    den = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300)
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / den, 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * ab), axis=1)


@dataclass
class Probe:
    """A ray against one primitive: t of the surface (the plane for triangles, the nearest
    positive root or the closest approach for spheres), whether the surface is reached within
    tolerance, and whether the ray passes within tolerance of the primitive's boundary."""

    t: np.ndarray
    reached: np.ndarray
    near_boundary: np.ndarray
    tol: np.ndarray
    boundary: np.ndarray  # distance of the ray's surface point to the boundary / rim


def _tolerance(d, t, q, rel):
    size = np.maximum(np.abs(q).max(axis=1), np.abs(t) * np.linalg.norm(d, axis=1))
    return rel * np.maximum(1.0, np.where(np.isfinite(size), size, 1.0))


def probe(prims, o, d, rel):
    from .oracle import sphere_roots

    n = len(prims.kind)
    t = np.full(n, np.inf)
    reached = np.zeros(n, bool)
    near = np.zeros(n, bool)
    tol = np.zeros(n)
    boundary = np.full(n, np.inf)
    tri = prims.kind == 1
    if tri.any():
        v = prims.tris[tri]
        oo, dd = o[tri], d[tri]
        nrm = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
        den = np.einsum("ij,ij->i", dd, nrm)
        with np.errstate(divide="ignore", invalid="ignore"):
            tt = np.einsum("ij,ij->i", v[:, 0] - oo, nrm) / den
        tt = np.where(np.isfinite(tt), tt, np.inf)
        q = oo + np.where(np.isfinite(tt), tt, 0)[:, None] * dd
        edge = np.min([_seg_dist(q, v[:, a], v[:, b]) for a, b in ((0, 1), (1, 2), (2, 0))],
                      axis=0)
        # Inside test by the signs of the sub-triangle normals.
        inside = np.ones(len(v), bool)
        for a, b in ((0, 1), (1, 2), (2, 0)):
            inside &= np.einsum("ij,ij->i", np.cross(v[:, b] - v[:, a], q - v[:, a]), nrm) >= 0
        tl = _tolerance(dd, tt, q, rel)
        t[tri] = tt
        tol[tri] = tl
        reached[tri] = (tt > 0) & np.isfinite(tt) & (inside | (edge <= tl))
        near[tri] = reached[tri] & (edge <= tl)
        boundary[tri] = edge
    sph = prims.kind == 0
    if sph.any():
        s = prims.spheres[sph]
        oo, dd = o[sph], d[sph]
        c, r = s[:, :3], s[:, 3]
        t0, t1 = sphere_roots(oo, dd, c, r)
        tt = np.where(t0 > 0, t0, np.where(t1 > 0, t1, np.nan))
        # Closest approach where the ray misses (or the sphere is behind).
        tc = np.einsum("ij,ij->i", c - oo, dd) / np.einsum("ij,ij->i", dd, dd)
        tt = np.where(np.isnan(tt), tc, tt)
        q = oo + tt[:, None] * dd
        perp = np.linalg.norm(np.cross(c - oo, dd), axis=1) / np.linalg.norm(dd, axis=1)
        tl = _tolerance(dd, tt, q, rel)
        t[sph] = tt
        tol[sph] = tl
        reached[sph] = (tt > 0) & (perp <= np.abs(r) + tl)
        near[sph] = reached[sph] & (np.abs(perp - np.abs(r)) <= tl)
        boundary[sph] = np.abs(perp - np.abs(r))
    return Probe(t, reached, near, tol, boundary)


def classify(o, d, lum, l_mapped, l_retri, orc, o_unmatched, rel):
    """Class name per differing pixel (see the module doc). `lum` and `orc` are the lumis and
    oracle primitives hit (Prims), `l_mapped` whether lumis's primitive has an oracle
    counterpart, `l_retri` whether it belongs to a polygon the two loaders triangulated
    differently, `o_unmatched` whether the oracle's triangle has no lumis counterpart."""
    n = len(o)
    out = np.full(n, "mismatch", object)
    a = probe(lum, o, d, rel)
    b = probe(orc, o, d, rel)
    dlen = np.linalg.norm(d, axis=1)
    l_kind, o_kind = lum.kind, orc.kind

    def rim(k):
        return "grazing" if k == 0 else "silhouette"

    for i in range(n):
        l_hit, o_hit = l_kind[i] >= 0, o_kind[i] >= 0
        if l_hit and not a.reached[i]:
            out[i] = "mismatch" if l_mapped[i] or l_retri[i] else "unmapped"
            continue  # lumis reports a primitive the ray does not reach
        if l_hit and o_hit:
            tol = max(a.tol[i], b.tol[i])
            if abs(a.t[i] - b.t[i]) * dlen[i] <= tol:
                if l_retri[i] and o_unmatched[i]:
                    out[i] = "retriangulated"
                elif a.near_boundary[i] or b.near_boundary[i]:
                    both_tri = l_kind[i] == 1 and o_kind[i] == 1
                    shared = both_tri and a.near_boundary[i] and b.near_boundary[i] and \
                        _share_edge(lum.tris[i], orc.tris[i], tol)
                    out[i] = "shared_edge" if shared else "edge"
                else:
                    out[i] = "tie"
            elif a.t[i] < b.t[i] and a.near_boundary[i]:
                out[i] = rim(l_kind[i])
            elif b.t[i] < a.t[i] and b.near_boundary[i]:
                out[i] = rim(o_kind[i])
        elif o_hit and b.near_boundary[i]:
            out[i] = rim(o_kind[i])
        elif l_hit and a.near_boundary[i]:
            out[i] = rim(l_kind[i])
        if out[i] == "mismatch" and l_hit and not (l_mapped[i] or l_retri[i]):
            out[i] = "unmapped"
    return out, a, b


def _share_edge(t1, t2, tol):
    """Whether two triangles have two corners in common (within `tol`, as the two loaders may
    round transformed vertices differently)."""
    same = (np.abs(t1[:, None, :] - t2[None, :, :]) <= tol).all(axis=2)
    return int(same.any(axis=1).sum()) >= 2


# ---------------------------------------------------------------------------------------------
# Scene mode


def expected_normals(geom, hits):
    """The shading normal lumis should report for each oracle hit (unit, world space)."""
    n = hits.normal.copy()
    tri = hits.kind == 1
    if tri.any():
        idx = hits.index[tri]
        vn = geom.vertex_normals[idx]  # (k, 3, 3)
        smooth = ~np.isnan(vn).any(axis=(1, 2))
        u, v = hits.u[tri], hits.v[tri]
        w = np.stack([1 - u - v, u, v], axis=1)
        s = np.einsum("kc,kcj->kj", w, np.nan_to_num(vn))
        length = np.linalg.norm(s, axis=1)
        ok = smooth & (length > 0)
        s = s / np.where(length > 0, length, 1)[:, None]
        ng = hits.normal[tri]
        s = np.where((np.einsum("ij,ij->i", s, ng) < 0)[:, None], -s, s)
        n[tri] = np.where(ok[:, None], s, ng)
    return n


def position_error(geom, hits, p):
    """Per oracle hit, how far lumis's float32 hit point may be off the surface: a few ulps of
    the largest corner coordinate for triangles (lumis interpolates the corners), of the hit
    point's own coordinates for spheres (lumis projects onto the sphere in float64)."""
    out = np.zeros(len(hits.kind))
    sph, tri = hits.kind == 0, hits.kind == 1
    out[sph] = POS_EPS_SPHERE * np.abs(p[sph]).max(axis=1)
    out[tri] = POS_EPS_TRIANGLE * np.abs(geom.triangles[hits.index[tri]]).max(axis=(1, 2))
    return out


def normal_rate(geom, hits):
    """Per oracle hit, how fast the expected normal turns per unit of distance along the
    surface: 1/r on spheres, 0 on flat triangles, and on smooth ones the largest difference of
    two corner normals over their distance, divided by the length of the interpolated
    (unnormalised) normal."""
    k = np.zeros(len(hits.kind))
    sph = hits.kind == 0
    k[sph] = 1.0 / np.abs(geom.spheres[hits.index[sph], 3])
    tri = hits.kind == 1
    if tri.any():
        idx = hits.index[tri]
        v, vn = geom.triangles[idx], geom.vertex_normals[idx]
        smooth = ~np.isnan(vn).any(axis=(1, 2))
        vn = np.nan_to_num(vn)
        rate = np.zeros(len(idx))
        for a, b in ((0, 1), (1, 2), (2, 0)):
            dist = np.linalg.norm(v[:, a] - v[:, b], axis=1)
            rate = np.maximum(rate, np.linalg.norm(vn[:, a] - vn[:, b], axis=1)
                              / np.maximum(dist, 1e-300))
        u, w = hits.u[tri], hits.v[tri]
        s = np.einsum("kc,kcj->kj", np.stack([1 - u - w, u, w], axis=1), vn)
        length = np.linalg.norm(s, axis=1)
        k[tri] = np.where(smooth, rate / np.maximum(length, 1e-12), 0.0)
    return k


def channel_stats(diff, mask, allow, fail, warn, height, width, args):
    """idiff-style statistics of `diff` ((H*W, C) differences) over the pixels of `mask`.

    Each pixel has an allowance: the error that the float32 limits of lumis's ray and hit point
    can cause there. Where it is at most `warn` (well-conditioned pixels, nearly all), the
    pixels go through ImageBufAlgo.compare with the plain thresholds. Elsewhere (grazing
    incidence, small spheres seen from afar) the pixel is ill-conditioned: its thresholds are
    `warn + allowance` and `fail + allowance`. The counts of both sets decide, as in idiff."""
    ill = mask & (allow > warn)
    regular = mask & ~ill
    c = diff.shape[1]
    # compare() loses count on inf and NaN; they become a huge finite error (and are counted).
    nonfinite = int((~np.isfinite(diff[mask])).any(axis=1).sum())
    diff = np.nan_to_num(diff, nan=BIG, posinf=BIG, neginf=-BIG)
    d = np.where(regular[:, None], diff, 0.0).reshape(height, width, c)
    res = oiio.ImageBufAlgo.compare(to_buf(d), to_buf(np.zeros_like(d)), fail, warn)
    _check_compare(res)
    n_reg = int(regular.sum())
    scale = d.size / max(n_reg * c, 1)  # compare averages over every pixel
    err = np.abs(diff[ill]).max(axis=1) if ill.any() else np.zeros(0)
    ill_warn = err > warn + allow[ill]
    ill_fail = err > fail + allow[ill]
    nwarn = int(res.nwarn) + int(ill_warn.sum())
    nfail = int(res.nfail) + int(ill_fail.sum())
    npels = max(int(mask.sum()), 1)
    if nfail > args.failpercent / 100.0 * npels or res.maxerror > args.hardfail:
        code = EXIT_FAIL
    elif nwarn > args.warnpercent / 100.0 * npels or res.maxerror > args.hardwarn:
        code = EXIT_WARN
    else:
        code = EXIT_OK
    stats = {
        "status": STATUS[code], "code": code, "fail": fail, "warn": warn,
        "compared": n_reg, "nfail": nfail, "nwarn": nwarn,
        "maxerror": float(res.maxerror),
        "max_at": [int(res.maxx), int(res.maxy)] if res.maxerror else None,
        "meanerror": float(res.meanerror) * scale,
        "rms_error": float(res.rms_error) * math.sqrt(scale),
        "PSNR": float(res.PSNR),
        "nonfinite": nonfinite,
        "ill_conditioned": int(ill.sum()),
        "ill_conditioned_nwarn": int(ill_warn.sum()),
        "ill_conditioned_nfail": int(ill_fail.sum()),
    }
    if ill.any():
        stats["ill_conditioned_max_error"] = float(err.max())
        stats["ill_conditioned_max_allowance"] = float(allow[ill].max())
        # The worst pixel relative to its own warning threshold (<= 1: no warning).
        stats["ill_conditioned_worst_over_warn"] = float((err / (warn + allow[ill])).max())
    bad = np.flatnonzero(ill)[ill_warn][:10]
    if len(bad):
        stats["ill_conditioned_over_threshold"] = [
            {"pixel": [int(i % width), int(i // width)], "error": float(np.abs(diff[i]).max()),
             "allowance": float(allow[i])} for i in bad]
    return stats


def render(scene, out, args):
    cmd = ["render", scene, "-o", out, "--width", args.width, "--height", args.height,
           "--spp", args.spp, "--quiet"]
    if args.float:
        cmd.append("--float")
    for extra in args.render_arg or []:
        cmd.append(extra)
    try:
        lumis_bin.run(cmd, "lumis render")
    except lumis_bin.LumisError as e:
        raise ToolError(str(e)) from e


def check_scene(scene, args, fail_spec, warn_spec, diff_path):
    from .geometry import LoadError, load_geometry
    from .idmap import IdMap, snap_to_lumis
    from .oracle import Oracle

    t_start = time.perf_counter()
    timings = {}
    report = {"scene": str(scene)}
    checks = Checks()
    report["checks"] = checks.items
    with tempfile.TemporaryDirectory(prefix="crosscheck-exr-") as tmp:
        if args.exr:
            exr_path = Path(args.exr)
            spp = None
        else:
            exr_path = Path(tmp) / "render.exr"
            if args.keep_exr:
                Path(args.keep_exr).mkdir(parents=True, exist_ok=True)
                exr_path = Path(args.keep_exr) / (Path(scene).name + ".exr")
            t0 = time.perf_counter()
            render(scene, exr_path, args)
            timings["render_s"] = time.perf_counter() - t0
            spp = args.spp
        report["exr"] = str(exr_path)
        exr = read_exr(exr_path)
    width, height = exr.size
    expect_w = width if args.exr else args.width
    expect_h = height if args.exr else args.height
    report["size"] = [width, height]
    complete = check_layout(exr, expect_w, expect_h, args.float, checks)
    w2c, w2ndc = check_header(exr.spec, spp, checks)
    if not complete or w2c is None or w2ndc is None:
        return finish(report, checks, {}, t_start, timings)

    px = exr.pixels
    z, prim, obj = px["Z"], px["id.prim"], px["id.object"]
    nrm = np.stack([px["N.X"], px["N.Y"], px["N.Z"]], axis=-1)

    # AOV value contract.
    miss = prim == -1
    hit = ~miss
    report["pixels"] = {"total": int(z.size), "lumis_hits": int(hit.sum())}
    checks.add("ids are integers >= -1", np.all((prim == np.round(prim)) & (prim >= -1))
               and np.all((obj == np.round(obj)) & (obj >= -1)), "")
    checks.add("misses: Z = +inf, N = 0, id.object = -1",
               np.all(np.isposinf(z[miss])) and np.all(nrm[miss] == 0)
               and np.all(obj[miss] == -1), f"{int(miss.sum())} misses")
    checks.add("hits: Z finite > 0", np.all(np.isfinite(z[hit]) & (z[hit] > 0)),
               f"{int(np.sum(~(np.isfinite(z[hit]) & (z[hit] > 0))))} bad")
    nlen = np.linalg.norm(nrm[hit].astype(np.float64), axis=-1)
    checks.add("hits: |N| = 1", np.all(np.abs(nlen - 1) <= 1e-5),
               f"max ||N| - 1| {np.abs(nlen - 1).max() if nlen.size else 0:.2e}")
    checks.add("hits: id.object >= 0", np.all(obj[hit] >= 0), "")
    pairs = np.unique(np.stack([prim[hit], obj[hit]], 1), axis=0)
    checks.add("one object id per primitive", len(pairs) == len(np.unique(pairs[:, 0])),
               f"{len(np.unique(pairs[:, 0]))} primitives, {len(pairs)} (prim, object) pairs")
    rgba_nan = sum(int(np.isnan(px[c]).sum()) for c in RGBA)
    checks.add("RGBA has no NaN", rgba_nan == 0, f"{rgba_nan} NaN samples")

    cam = camera_rays(w2c, w2ndc, width, height, checks)

    # The oracle, on the independently loaded geometry. Primitives matched to lumis's take its
    # exact float32 coordinates (snap_to_lumis), so that one-ulp differences between the two
    # loaders' transforms stay out of the comparison; the largest such move is reported.
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            # trimesh's texture handling warns about NaN medians on untextured glTF; noise.
            warnings.simplefilter("ignore", RuntimeWarning)
            geom = load_geometry(scene)
    except (LoadError, OSError) as e:
        raise ToolError(f"{scene}: the independent loader failed: {e}") from e
    try:
        l_tris, l_spheres = lumis_bin.primitives(scene)
    except lumis_bin.LumisError as e:
        raise ToolError(str(e)) from e
    idmap = IdMap.build(geom, l_tris, l_spheres)
    geom, deviation = snap_to_lumis(geom, idmap, l_tris, l_spheres)
    lprims = LumisPrims(l_tris, l_spheres)
    timings["load_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    hits = Oracle(geom).trace(cam.rays)
    timings["oracle_s"] = time.perf_counter() - t0
    report["geometry"] = {"triangles": len(geom.triangles), "spheres": len(geom.spheres),
                          "smooth_triangles": int((~np.isnan(geom.vertex_normals)
                                                   .any(axis=(1, 2))).sum()),
                          "normal_mapped_triangles": int(geom.triangle_normal_mapped.sum()),
                          "normal_mapped_spheres": int(geom.sphere_normal_mapped.sum()),
                          "lumis_triangles": len(l_tris), "lumis_spheres": len(l_spheres)}
    report["idmap"] = {**idmap.summary(), "max_vertex_deviation": deviation}
    if hasattr(idmap, "loader_mismatches"):
        loader_mismatches = idmap.loader_mismatches()
    else:
        loader_mismatches = (idmap.unmatched_lumis_triangles + idmap.unmatched_oracle_triangles
                             + idmap.unmatched_lumis_spheres + idmap.unmatched_oracle_spheres)
    checks.add("every primitive maps between lumis and the oracle (retriangulated polygons "
               "aside)", loader_mismatches == 0, json.dumps(idmap.summary()),
               severity=EXIT_WARN)

    # ids.
    lp = prim.reshape(-1).astype(np.int64)
    l_kind, l_index = idmap.to_oracle(lp)
    same = (l_kind == hits.kind) & ((l_index == hits.index) | (hits.kind < 0))
    cls = np.full(lp.shape, "match", object)
    diff_idx = np.flatnonzero(~same)
    o64 = cam.rays[:, 0:3].astype(np.float64)
    d64 = cam.rays[:, 3:6].astype(np.float64)
    if len(diff_idx):
        retri = getattr(idmap, "lumis_retriangulated", None)
        lpd = lp[diff_idx]
        l_retri = np.zeros(len(diff_idx), bool)
        if retri is not None:
            ok = (lpd >= 0) & (lpd < len(retri))
            l_retri[ok] = retri[lpd[ok]]
        matched_o = np.zeros(len(geom.triangles), bool)
        matched_o[idmap.index[idmap.kind == 1]] = True
        ok_kind, ok_index = hits.kind[diff_idx], hits.index[diff_idx]
        o_unmatched = np.zeros(len(diff_idx), bool)
        o_tri = ok_kind == 1
        o_unmatched[o_tri] = ~matched_o[ok_index[o_tri]]
        cls[diff_idx], pa, pb = classify(o64[diff_idx], d64[diff_idx], lprims.of(lpd),
                                         l_kind[diff_idx] >= 0, l_retri,
                                         Prims.of_oracle(geom, ok_kind, ok_index), o_unmatched,
                                         args.edge_tol)
    counts = {c: int(np.sum(cls == c)) for c in CLASSES}
    bad = counts["mismatch"] + counts["unmapped"]
    id_stats = {"status": STATUS[EXIT_FAIL if bad else EXIT_OK], "code": EXIT_FAIL if bad else 0,
                "oracle_hits": int((hits.kind >= 0).sum()), **counts}
    examples = {}
    for k, i in enumerate(diff_idx):
        c = cls[i]
        if len(examples.setdefault(c, [])) >= 5:
            continue
        examples[c].append({
            "pixel": [int(i % width), int(i // width)],
            "lumis_prim": int(lp[i]), "lumis_as_oracle": [int(l_kind[i]), int(l_index[i])],
            "oracle": [int(hits.kind[i]), int(hits.index[i])],
            "lumis_Z": float(z.reshape(-1)[i]), "oracle_t": float(hits.t[i]),
            "t_on_lumis_prim": float(pa.t[k]), "t_on_oracle_prim": float(pb.t[k]),
            "lumis_prim_boundary_distance": float(pa.boundary[k]),
            "oracle_prim_boundary_distance": float(pb.boundary[k]),
            "tolerance": float(max(pa.tol[k], pb.tol[k]))})
    if examples:
        id_stats["examples"] = examples

    # How far each oracle hit point may move for a ray error of --ray-eps (lateral offset
    # eps * (distance + |eye|)), divided by the cosine of incidence: the allowance of Z
    # (relative) and N (times the normal's rate of change along the surface) per pixel.
    o_hit = hits.kind >= 0
    l_hit = lp >= 0
    dlen = np.linalg.norm(d64, axis=1)
    t_hit = np.where(o_hit, hits.t, 0.0)
    cos_i = np.abs(np.einsum("ij,ij->i", d64 / dlen[:, None], hits.normal))
    p = o64 + t_hit[:, None] * d64
    # A ray moved sideways by `lateral` meets the surface `lateral / cos` further along it
    # (which turns the normal) and `lateral * tan` deeper (which changes Z); a surface point
    # off by `offset` along the normal changes both by `offset / cos`.
    lateral = args.ray_eps * (t_hit * dlen + max(1.0, float(np.abs(cam.eye).max())))
    offset = position_error(geom, hits, p)
    cos_c = np.maximum(cos_i, 1e-12)
    dp = (lateral + offset) / cos_c
    dz = (lateral * np.sqrt(np.maximum(1 - cos_i ** 2, 0)) + offset) / cos_c
    kappa = normal_rate(geom, hits)

    # Z: relative error where both saw the same surface.
    z_mask = l_hit & o_hit & ((cls == "match") | np.isin(cls, list(SAME_DEPTH)))
    z_oracle = np.where(o_hit, (p - cam.eye) @ cam.forward, np.inf)
    z_l = z.reshape(-1).astype(np.float64)
    rel = np.zeros_like(z_l)
    rel[z_mask] = (z_l[z_mask] - z_oracle[z_mask]) / z_oracle[z_mask]
    allow_z = np.where(z_mask, dz / np.where(o_hit, np.abs(z_oracle), 1.0), 0.0)
    if args.no_allowance:
        allow_z[:] = 0
    zf, zw = threshold_for("Z", fail_spec), threshold_for("Z", warn_spec)
    z_stats = channel_stats(rel[:, None], z_mask, allow_z, zf, zw, height, width, args)
    z_stats["kind"] = "relative"
    if z_mask.any():
        z_stats["max_abs_difference"] = float(np.abs(z_l[z_mask] - z_oracle[z_mask]).max())

    # N: where both hit the same primitive (or the same plane of a retriangulated polygon,
    # when flat), not normal-mapped.
    n_exp = expected_normals(geom, hits)
    mapped = np.zeros(lp.shape, bool)
    sph, tri = hits.kind == 0, hits.kind == 1
    mapped[sph] = geom.sphere_normal_mapped[hits.index[sph]]
    mapped[tri] = geom.triangle_normal_mapped[hits.index[tri]]
    flat = np.zeros(lp.shape, bool)
    flat[tri] = np.isnan(geom.vertex_normals[hits.index[tri]]).any(axis=(1, 2))
    n_base = l_hit & ((cls == "match") | ((cls == "retriangulated") & flat))
    n_mask = n_base & ~mapped
    n_l = nrm.reshape(-1, 3).astype(np.float64)
    dn = np.zeros_like(n_l)
    dn[n_mask] = n_l[n_mask] - n_exp[n_mask]
    allow_n = np.where(n_mask, dp * kappa, 0.0)
    if args.no_allowance:
        allow_n[:] = 0
    nf, nw = threshold_for("N", fail_spec), threshold_for("N", warn_spec)
    n_stats = channel_stats(dn, n_mask, allow_n, nf, nw, height, width, args)
    n_stats["kind"] = "absolute"
    nm = n_base & mapped
    n_stats["normal_mapped_excluded"] = int(nm.sum())
    if nm.any():
        # Information only: does the layer carry the normal map's perturbation?
        err = np.abs(n_l[nm] - n_exp[nm]).max(axis=1)
        n_stats["normal_mapped_matching_unperturbed"] = int(np.sum(err <= nf + (dp * kappa)[nm]))
    ki = hits.kind[n_mask]
    n_stats["compared_by_kind"] = {"triangles_smooth": int(np.sum((ki == 1) & ~flat[n_mask])),
                                   "triangles_flat": int(np.sum((ki == 1) & flat[n_mask])),
                                   "spheres": int(np.sum(ki == 0))}

    channels = {"id": id_stats, "Z": z_stats, "N": n_stats}
    if diff_path:
        code = {c: i for i, c in enumerate(CLASSES)}
        layers = {
            "Z.relerr": rel, "Z.allowance": allow_z,
            "N.X": dn[:, 0], "N.Y": dn[:, 1], "N.Z": dn[:, 2], "N.allowance": allow_n,
            "id.class": np.array([code[c] for c in cls], np.float64),
            "oracle.Z": z_oracle,
            "oracle.N.X": n_exp[:, 0], "oracle.N.Y": n_exp[:, 1], "oracle.N.Z": n_exp[:, 2],
            "oracle.kind": hits.kind.astype(np.float64),
            "oracle.index": hits.index.astype(np.float64),
        }
        write_layers(diff_path, width, height, layers)
        report["diff"] = str(diff_path)
    return finish(report, checks, channels, t_start, timings)


def finish(report, checks, channels, t_start, timings):
    report["channels"] = channels
    code = checks.code()
    for c in channels.values():
        code = max(code, c["code"])
    report["status"] = STATUS[code]
    report["code"] = code
    timings["total_s"] = time.perf_counter() - t_start
    report["timings"] = {k: round(v, 3) for k, v in timings.items()}
    return report


def write_layers(path, width, height, layers):
    names = list(layers)
    data = np.stack([np.asarray(layers[n], np.float32).reshape(height, width) for n in names],
                    axis=-1)
    spec = oiio.ImageSpec(width, height, len(names), oiio.FLOAT)
    spec.channelnames = names
    spec.attribute("compression", "zip")
    buf = oiio.ImageBuf(spec)
    buf.set_pixels(oiio.ROI(0, width, 0, height, 0, 1, 0, len(names)), data)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    if not buf.write(str(path)):
        raise ToolError(f"cannot write {path}: {buf.geterror()}")


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
# Compare mode


def compare_files(a_path, b_path, args, fail_spec, warn_spec):
    report = {"a": str(a_path), "b": str(b_path), "channels": {}}
    try:
        a, b = read_exr(a_path), read_exr(b_path)
    except ToolError as e:
        report.update(status=STATUS[EXIT_FILE], code=EXIT_FILE, error=str(e))
        return report
    names_a, names_b = list(a.spec.channelnames), list(b.spec.channelnames)
    report["size"] = [list(a.size), list(b.size)]
    report["channel_names"] = [names_a, names_b]
    if a.size != b.size or sorted(names_a) != sorted(names_b) or a.nsubimages != b.nsubimages:
        report.update(status=STATUS[EXIT_SIZE], code=EXIT_SIZE,
                      error="the images differ in size, parts or channel names")
        return report
    report["type_differences"] = {n: [a.formats[n], b.formats[n]] for n in names_a
                                  if a.formats[n] != b.formats[n]}
    w, h = a.size
    code = EXIT_OK
    diff = {}
    for n in names_a:
        x, y = a.pixels[n].copy(), b.pixels[n].copy()
        equal = (x == y) | (np.isnan(x) & np.isnan(y))
        x[equal] = 0
        y[equal] = 0
        # Unequal pairs with an inf or NaN: a huge finite difference (compare() miscounts them).
        odd = ~np.isfinite(x) | ~np.isfinite(y)
        x[odd], y[odd] = 0, BIG
        stats = compare_stats(x, y, threshold_for(n, fail_spec), threshold_for(n, warn_spec),
                              w * h, args, args.failrelative, args.warnrelative)
        stats["different_pixels"] = int((~equal).sum())
        stats["nonfinite"] = int(odd.sum())
        report["channels"][n] = stats
        code = max(code, stats["code"])
        with np.errstate(invalid="ignore"):
            diff[n] = np.where(equal, 0.0, a.pixels[n].astype(np.float64) - b.pixels[n])
    if args.diff:
        write_layers(args.diff, w, h, diff)
        report["diff"] = str(args.diff)
    report.update(status=STATUS[code], code=code)
    return report


def print_compare(r, verbose):
    print(f"{r['status'].upper():6} {r['a']} vs {r['b']}")
    if "error" in r:
        extra = (f": sizes {r['size']}, channels {r['channel_names']}" if "size" in r else "")
        print(f"    {r['error']}{extra}")
    for n, c in r["channels"].items():
        if c["code"] or verbose:
            print(f"    {n}: max {c['maxerror']:.3g} at {c['max_at']}, mean {c['meanerror']:.3g}"
                  f", {c['nwarn']} over {c['warn']}, {c['nfail']} over {c['fail']}"
                  + (f", {c['nonfinite']} with inf/NaN on one side" if c["nonfinite"] else "")
                  + f" -> {c['status']}")


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
