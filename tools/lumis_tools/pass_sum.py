"""check_passes_sum's logic: where the light-path and per-light layers of a lumis EXR are in
either channel layout, and whether they add up, pixel by pixel, within float rounding:

    R, G, B (beauty) = diffuse + specular + reflection + refraction + emission + ambient
                       + background
    diffuse + specular = the sum of the light.<name> layers

Pure numpy on {channel name: (H, W) array}; reading the file is the tool's (OpenImageIO)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# lumis's pass layer names, and Blender's for the same passes (`--layout blender`).
PASSES = ("diffuse", "specular", "reflection", "refraction", "emission", "ambient", "background")
BLENDER_PASSES = {"diffuse": "DiffDir", "specular": "GlossDir", "reflection": "GlossInd",
                  "refraction": "TransInd", "emission": "Emit", "ambient": "Ambient",
                  "background": "Env"}
# Per layout: the beauty layer's prefix, a pass layer's prefix, a light layer's prefix.
LAYOUTS = {
    "lumis": {"beauty": "", "pass": "", "light": "light."},
    "blender": {"beauty": "ViewLayer.Combined.", "pass": "ViewLayer.",
                "light": "ViewLayer.Combined_"},
}
RGB = ("R", "G", "B")

# Tolerances (see tolerance()): float32's unit roundoff, half's.
U_FLOAT = 2.0 ** -24
U_HALF = 2.0 ** -11
REL_FLOOR = 1e-5
ABS = 1e-6


class LayerError(Exception):
    """The file lacks a layer the check needs, or has it with other channels."""


@dataclass
class Layers:
    """The channel names of the beauty and of each pass and light layer, as (R, G, B)."""

    layout: str
    beauty: tuple
    passes: dict  # lumis pass name -> (R, G, B) channel names
    lights: dict  # light name -> (R, G, B) channel names


def layout_of(names):
    """"blender" when the beauty is ViewLayer.Combined.*, "lumis" when it is R, G, B."""
    names = set(names)
    if {"ViewLayer.Combined." + c for c in RGB} <= names:
        return "blender"
    if set(RGB) <= names:
        return "lumis"
    raise LayerError("no beauty: neither R, G, B nor ViewLayer.Combined.R/G/B")


def find_layers(names):
    """The Layers of a file with channels `names`; LayerError names what is missing."""
    names = list(names)
    layout = layout_of(names)
    pre = LAYOUTS[layout]
    beauty = tuple(pre["beauty"] + c for c in RGB)
    passes, missing = {}, []
    for p in PASSES:
        layer = pre["pass"] + (BLENDER_PASSES[p] if layout == "blender" else p)
        channels = tuple(f"{layer}.{c}" for c in RGB)
        if all(c in names for c in channels):
            passes[p] = channels
        else:
            missing.append(layer)
    if missing:
        raise LayerError(f"{layout} layout without the pass layers {', '.join(missing)} "
                         "(rendered without --aov lightpaths?)")
    lights = {}
    for n in names:
        if n.startswith(pre["light"]) and n.endswith(".R"):
            light = n[len(pre["light"]):-2]
            channels = tuple(f"{pre['light']}{light}.{c}" for c in RGB)
            if not all(c in names for c in channels):
                raise LayerError(f"light layer {pre['light']}{light} lacks one of R, G, B")
            lights[light] = channels
    return Layers(layout, beauty, passes, lights)


def tolerance(samples=16, half_beauty=False, half_parts=False):
    """(relative, absolute) tolerance of a sum check.

    Float32 rounding: lumis adds a sample's terms (at most a few per pass and light) and then a
    pixel's samples, both for the beauty and for each pass, in different orders. The classic
    bound for a sum of n terms is (n - 1) u sum|terms| (u = 2^-24), so a pixel of `samples`
    samples whose samples have up to 32 terms in all stays within (samples + 32) u of the sum
    of the magnitudes; twice that, and at least 1e-5 (170 ulps: at 16 samples 5x the bound,
    and a missing or doubled term is 1e-3 of the pixel or more). A HALF beauty or HALF layers
    are each rounded once more, by at most u_half = 2^-11 relative. The absolute 1e-6 covers
    pixels where every term is ~0 (no relative scale), and is far below the smallest step of
    an 8-bit image (3e-4 in linear light)."""
    rel = max(REL_FLOOR, 2.0 * (samples + 32) * U_FLOAT)
    rel += U_HALF * (int(half_beauty) + int(half_parts))
    return rel, ABS


@dataclass
class SumCheck:
    """How far the parts' sum is from the total, over every pixel and channel."""

    pixels: int
    max_abs: float  # largest |sum(parts) - total|
    max_rel: float  # largest |sum(parts) - total| / magnitude where the magnitude is > 0
    bad: int  # pixels where some channel is outside the tolerance
    worst: tuple  # (x, y) of the pixel furthest beyond its tolerance (relative to it)
    worst_detail: str
    nonfinite: int  # pixels with a NaN or infinite value in any part or the total

    @property
    def ok(self):
        return self.bad == 0 and self.nonfinite == 0


def check_sum(parts, total, rel, abs_tol):
    """Checks sum(parts) == total per pixel and channel within rel x magnitude + abs_tol,
    magnitude = max(sum |parts|, |total|) of that channel (rounding scales with the terms).
    `parts`: list of (H, W, 3) arrays; `total`: (H, W, 3). Sums in float64."""
    total = np.asarray(total, np.float64)
    stack = np.stack([np.asarray(p, np.float64) for p in parts]) if parts else \
        np.zeros((1,) + total.shape)
    finite = np.isfinite(stack).all(axis=0).all(axis=-1) & np.isfinite(total).all(axis=-1)
    s = stack.sum(axis=0)
    err = np.where(finite[..., None], np.abs(s - total), 0.0)
    mag = np.where(finite[..., None], np.maximum(np.abs(stack).sum(axis=0), np.abs(total)), 0.0)
    allowed = rel * mag + abs_tol
    over = err / allowed  # > 1: outside the tolerance
    bad = (over > 1.0).any(axis=-1) & finite
    with np.errstate(divide="ignore", invalid="ignore"):
        relerr = np.where(mag > 0, err / mag, 0.0)
    y, x, c = np.unravel_index(int(np.argmax(over)), over.shape)
    detail = (f"channel {RGB[c]}: parts sum to {s[y, x, c]:.9g}, total {total[y, x, c]:.9g}, "
              f"difference {err[y, x, c]:.3g}, allowed {allowed[y, x, c]:.3g}")
    return SumCheck(pixels=int(finite.size), max_abs=float(err.max(initial=0.0)),
                    max_rel=float(relerr.max(initial=0.0)), bad=int(bad.sum()),
                    worst=(int(x), int(y)), worst_detail=detail,
                    nonfinite=int((~finite).sum()))


def rgb(channels, names):
    """The (H, W, 3) array of channels `names` (R, G, B) from {name: (H, W)}."""
    return np.stack([np.asarray(channels[n], np.float64) for n in names], axis=-1)


def check_channels(channels, formats, samples=16):
    """Both checks on one file's channels ({name: (H, W)}) and pixel types ({name: "half" or
    "float"}): returns (Layers, passes SumCheck, lights SumCheck or None without light layers,
    the tolerance used)."""
    layers = find_layers(channels)
    half_beauty = any(formats.get(n) == "half" for n in layers.beauty)
    part_names = [n for ch in [*layers.passes.values(), *layers.lights.values()] for n in ch]
    half_parts = any(formats.get(n) == "half" for n in part_names)
    rel, abs_tol = tolerance(samples, half_beauty, half_parts)
    passes = check_sum([rgb(channels, ch) for ch in layers.passes.values()],
                       rgb(channels, layers.beauty), rel, abs_tol)
    lights = None
    if layers.lights:
        direct = rgb(channels, layers.passes["diffuse"]) + rgb(channels, layers.passes["specular"])
        # Only the parts were rounded (both sides are passes): the HALF-beauty allowance of
        # the first check does not apply.
        lrel, _ = tolerance(samples, False, half_parts)
        lights = check_sum([rgb(channels, ch) for ch in layers.lights.values()], direct, lrel,
                           abs_tol)
    return layers, passes, lights, (rel, abs_tol)
