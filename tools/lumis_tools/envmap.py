"""Latitude-longitude environment maps for the checks, in numpy: the orientation convention
(Mitsuba 3's `envmap`, which lumis's `[environment]` follows), a test map that no mirroring or
quarter turn leaves unchanged, a Radiance RGBE writer and reader, and Mitsuba's bilinear lookup.

The convention, as src/emitters/envmap.cpp of Mitsuba 3 has it: a direction d = (x, y, z),
Y up, in the emitter's own frame shows the texel at

    u = atan2(x, -z) / 2pi  wrapped to [0, 1),   v = acos(y) / pi   (v = 0: the top row),

so u = 0 looks along -Z, u = 1/4 along +X, u = 1/2 along +Z, u = 3/4 along -X. A rotation of
theta degrees (lumis's `rotation`, Mitsuba's `<rotate y="1" angle="theta"/>` as the emitter's
to_world) turns the map about +Y: a world direction d is looked up at R_y(-theta) d, where R_y
is the right-handed rotation [[c, 0, s], [0, 1, 0], [-s, 0, c]]."""

from __future__ import annotations

from pathlib import Path

import numpy as np


def direction_to_uv(d):
    """(u, v) of unit directions `d` (..., 3) in the map's own frame (see the module doc)."""
    d = np.asarray(d, np.float64)
    u = np.arctan2(d[..., 0], -d[..., 2]) / (2.0 * np.pi)
    return u - np.floor(u), np.arccos(np.clip(d[..., 1], -1.0, 1.0)) / np.pi


def uv_to_direction(u, v):
    """The unit direction (..., 3) that `direction_to_uv` maps to (u, v)."""
    phi, theta = 2.0 * np.pi * np.asarray(u, np.float64), np.pi * np.asarray(v, np.float64)
    return np.stack([np.sin(phi) * np.sin(theta), np.cos(theta),
                     -np.cos(phi) * np.sin(theta)], axis=-1)


def rotation_y(degrees):
    """The 3x3 right-handed rotation about +Y (Mitsuba's `rotate y="1"`)."""
    t = np.radians(degrees)
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def world_to_map(d, rotation_deg):
    """World directions `d` (..., 3) in the frame of a map turned by `rotation_deg`."""
    # R^-1 = R^T, applied to row vectors: d @ R.
    return np.asarray(d, np.float64) @ rotation_y(rotation_deg)


# The test map's coloured patches: (name, direction in the map's frame, radius in degrees, RGB).
# Each sits in its own part of the sphere and no two are alike under u -> -u (a mirrored map)
# or a quarter turn, so a wrong convention moves colours the comparison sees.
PATCHES = (
    ("red +X", (1.0, 0.15, 0.0), 16.0, (3.0, 0.15, 0.1)),
    ("green -X", (-1.0, 0.35, 0.0), 12.0, (0.15, 2.2, 0.2)),
    ("blue +Z", (0.0, -0.1, 1.0), 20.0, (0.2, 0.3, 3.0)),
    ("yellow -Z", (0.0, 0.05, -1.0), 10.0, (2.5, 2.0, 0.1)),
    ("magenta", (0.7, 0.5, -0.5), 9.0, (2.0, 0.2, 2.0)),
    ("cyan", (-0.6, -0.45, 0.65), 14.0, (0.1, 1.8, 1.8)),
)


def orientation_map(width=512, height=256):
    """A float32 (height, width, 3) lat-long map in linear RGB: a smooth sky over a darker
    ground whose tint also varies with azimuth, and the soft-edged PATCHES.

    Smooth on the scale of a texel (patch edges fade over several degrees), so engines that
    place texel centres or interpolate slightly differently (Mitsuba's rows span the poles,
    v = j / (H - 1); its columns sit at (i + 0.5) / W) agree to well under the sampling noise,
    while every feature is wide enough to be seen at ~100 pixels."""
    v, u = np.meshgrid((np.arange(height) + 0.5) / height, (np.arange(width) + 0.5) / width,
                       indexing="ij")
    d = uv_to_direction(u, v)
    y = d[..., 1]
    phi = 2.0 * np.pi * u
    sky = np.stack([0.35 + 0.25 * y, 0.5 + 0.25 * y, 0.8 + 0.2 * y], axis=-1)
    ground = np.stack([0.28, 0.2, 0.12]) * np.ones_like(sky)
    up = 0.5 + 0.5 * np.tanh(y / 0.06)[..., None]  # the horizon, a few degrees wide
    img = up * sky + (1.0 - up) * ground
    img *= (1.0 + 0.3 * np.sin(phi + 0.6))[..., None]  # no azimuth is like another
    for _, centre, radius, rgb in PATCHES:
        c = np.asarray(centre, np.float64)
        c /= np.linalg.norm(c)
        angle = np.degrees(np.arccos(np.clip(d @ c, -1.0, 1.0)))
        # Full colour inside the radius, fading to nothing over the next 40% of it.
        w = np.clip((1.4 * radius - angle) / (0.4 * radius), 0.0, 1.0)
        w = w * w * (3.0 - 2.0 * w)
        img = img * (1.0 - w[..., None]) + w[..., None] * np.asarray(rgb)
    return img.astype(np.float32)


# --- Radiance RGBE ----------------------------------------------------------------------------


def rgbe_encode(rgb):
    """(H, W, 4) uint8 RGBE of linear RGB (Greg Ward's shared exponent, mantissas truncated,
    as Bruce Walter's rgbe.c writes them)."""
    rgb = np.asarray(rgb, np.float64)
    m = rgb.max(axis=-1)
    frac, exp = np.frexp(m)  # m = frac * 2^exp, frac in [0.5, 1)
    scale = np.where(m > 1e-32, frac * 256.0 / np.where(m > 1e-32, m, 1.0), 0.0)
    out = np.zeros(rgb.shape[:-1] + (4,), np.uint8)
    out[..., :3] = np.clip(np.floor(rgb * scale[..., None]), 0, 255)
    out[..., 3] = np.where(m > 1e-32, exp + 128, 0)
    return out


def rgbe_decode(rgbe):
    """Linear RGB (float64) of RGBE bytes: mantissa x 2^(e - 136), 0 where e = 0 (rgbe.c's
    rule; Radiance's own reader adds half a step to the mantissa, a difference of at most 0.4%
    of a channel's value that the image checks' tolerances cover)."""
    rgbe = np.asarray(rgbe)
    e = rgbe[..., 3].astype(np.int32)
    f = np.where(e > 0, np.ldexp(1.0, e - 136), 0.0)
    return rgbe[..., :3].astype(np.float64) * f[..., None]


def write_hdr(path: Path, rgb):
    """A Radiance .hdr of `rgb` (H, W, 3), flat (not run-length encoded) scanlines, top row
    first. A flat scanline whose first pixel reads 2, 2, <128 would be taken for a run-length
    one by readers, so such a map is refused rather than written ambiguously."""
    rgbe = rgbe_encode(rgb)
    h, w = rgbe.shape[:2]
    first = rgbe[:, 0]
    if 8 <= w <= 0x7FFF and ((first[:, 0] == 2) & (first[:, 1] == 2) & (first[:, 2] < 128)).any():
        raise ValueError("a scanline would read as run-length encoded; change the map")
    header = f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n".encode("ascii")
    Path(path).write_bytes(header + rgbe.tobytes())


def read_hdr(path: Path):
    """The flat RGBE files write_hdr writes, decoded (float64 (H, W, 3)); for the tests."""
    data = Path(path).read_bytes()
    head, sep, rest = data.partition(b"\n\n")
    size_line, _, pixels = rest.partition(b"\n")
    _, h, _, w = size_line.split()
    h, w = int(h), int(w)
    if not head.startswith(b"#?RADIANCE") or len(pixels) != 4 * w * h:
        raise ValueError(f"{path}: not a flat RGBE file of {w}x{h}")
    return rgbe_decode(np.frombuffer(pixels, np.uint8).reshape(h, w, 4))


# --- Mitsuba's lookup -------------------------------------------------------------------------


def lookup_bilinear(img, u, v):
    """The map at (u, v) as Mitsuba's envmap evaluates it: bilinear between texels, columns at
    (i + 0.5) / W wrapping around, rows at v = j / (H - 1) (the top row at the pole)."""
    img = np.asarray(img, np.float64)
    h, w = img.shape[:2]
    padded = np.concatenate([img, img[:, :1]], axis=1)  # the periodic column
    x = np.asarray(u, np.float64) - 0.5 / w
    x = (x - np.floor(x)) * w
    y = np.clip(np.asarray(v, np.float64), 0.0, 1.0) * (h - 1)
    x0 = np.minimum(np.floor(x).astype(np.int64), w - 1)
    y0 = np.minimum(np.floor(y).astype(np.int64), h - 2)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    top = (1 - fx) * padded[y0, x0] + fx * padded[y0, x0 + 1]
    bottom = (1 - fx) * padded[y0 + 1, x0] + fx * padded[y0 + 1, x0 + 1]
    return (1 - fy) * top + fy * bottom
