"""Writes a procedural HDR environment of our own making: a latitude-longitude sky for tests
and the README's pictures, whose markers show in a render whether the map was mirrored or
turned (numpy only; OpenImageIO for `.exr` output).

    python tools/make_sky.py --out sky.hdr                  # 512 x 256 Radiance RGBE
    python tools/make_sky.py --width 2048 --out sky.exr     # OpenEXR (needs OpenImageIO)
    python tools/make_sky.py --no-sun --out sky_nosun.hdr

Direction convention (Mitsuba 3's `envmap` emitter, which lumis's `[environment]` follows):
pixel (column i, row j) of a W x H map, at its centre u = (i + 0.5) / W in [0, 1) and
v = (j + 0.5) / H in [0, 1], shows the world direction (Y up)

    theta = v * pi  (0 = +Y, up),  phi = u * 2 pi,
    d = (sin(phi) sin(theta), cos(theta), -cos(phi) sin(theta)),

that is u = atan2(x, -z) / (2 pi) wrapped to [0, 1), v = acos(y) / pi. Column 0 (the left
edge) looks along -Z, a quarter of the way across along +X, the middle along +Z, three
quarters along -X; row 0 is the zenith. The options give directions as an azimuth
phi = 360 u in degrees (0 = -Z, 90 = +X, 180 = +Z, 270 = -X) and an elevation above the
horizon (90 - 180 v degrees).

What the map holds (linear RGB radiance; H = W / 2):

- sky above the horizon: (0.80, 0.88, 1.00) at the horizon blending to (0.20, 0.38, 0.95)
  at the zenith, by sqrt(sin(elevation));
- ground below it: brown-green (0.16, 0.14, 0.07) at the horizon, darkening to 60% of that
  at the nadir;
- the sun (unless --no-sun): a disk of angular radius 1.5 degrees, radiance
  --sun-radiance x (1.00, 0.93, 0.82) (default 1e4), at --sun-azimuth / --sun-elevation
  (default 135, 35: between +X and +Z, a third of the way up);
- four markers, squares 12 degrees on a side in azimuth and elevation, radiance ~5:
  red at azimuth 90 (+X), green at 180 (+Z), blue at 270 (-X), all 10 degrees up, and yellow
  at azimuth 45, 60 degrees up. Nothing else is coloured, so a mirrored map (red and blue
  swap sides) or a quarter turn (the colours move one place round) shows at once.

Every pixel is the mean of a fixed --samples x --samples grid of directions inside it, so the
edges of the sun and the markers are antialiased and the output is the same on every run.
Radiance .hdr is written by this module (flat scanlines, no run-length encoding, mantissas
truncated under the largest component's exponent as Ward's RGBE does); .exr as float RGB
through OpenImageIO."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from . import exitcodes

SKY_HORIZON = (0.80, 0.88, 1.00)
SKY_ZENITH = (0.20, 0.38, 0.95)
GROUND = (0.16, 0.14, 0.07)
NADIR_SHADE = 0.6  # the ground at the nadir, relative to the horizon
SUN_COLOUR = (1.00, 0.93, 0.82)
SUN_RADIUS_DEG = 1.5
MARKER_SIZE_DEG = 12.0
# (name, azimuth, elevation, RGB radiance): see the module docs.
MARKERS = (
    ("red", 90.0, 10.0, (5.0, 0.2, 0.2)),
    ("green", 180.0, 10.0, (0.2, 5.0, 0.2)),
    ("blue", 270.0, 10.0, (0.3, 0.3, 6.0)),
    ("yellow", 45.0, 60.0, (5.0, 4.5, 0.2)),
)
ROWS_PER_BAND = 32  # rows supersampled at once, to bound the memory at large widths


def direction(azimuth_deg, elevation_deg):
    """The unit world direction (x, y, z) at an azimuth and elevation (see the module docs)."""
    phi, el = math.radians(azimuth_deg), math.radians(elevation_deg)
    return (math.sin(phi) * math.cos(el), math.sin(el), -math.cos(phi) * math.cos(el))


def radiance(np, u, v, sun):
    """The map's radiance (..., 3) at map coordinates u, v (arrays of one shape); `sun` is
    None or (unit direction, RGB radiance)."""
    theta, phi = np.pi * v, 2.0 * np.pi * u
    d = np.stack([np.sin(phi) * np.sin(theta), np.cos(theta), -np.cos(phi) * np.sin(theta)],
                 axis=-1)
    sin_el = d[..., 1]
    up = np.sqrt(np.clip(sin_el, 0.0, 1.0))[..., None]
    sky = np.asarray(SKY_HORIZON) * (1.0 - up) + np.asarray(SKY_ZENITH) * up
    shade = 1.0 - (1.0 - NADIR_SHADE) * np.clip(-sin_el, 0.0, 1.0)
    ground = np.asarray(GROUND) * shade[..., None]
    out = np.where((sin_el >= 0.0)[..., None], sky, ground)
    azimuth = np.degrees(phi)
    elevation = 90.0 - np.degrees(theta)
    for _, az, el, rgb in MARKERS:
        d_az = (azimuth - az + 180.0) % 360.0 - 180.0
        inside = (np.abs(d_az) <= MARKER_SIZE_DEG / 2) & (np.abs(elevation - el) <= MARKER_SIZE_DEG / 2)
        out = np.where(inside[..., None], np.asarray(rgb), out)
    if sun is not None:
        sun_dir, sun_rgb = sun
        inside = d @ np.asarray(sun_dir) >= math.cos(math.radians(SUN_RADIUS_DEG))
        out = np.where(inside[..., None], np.asarray(sun_rgb), out)
    return out


def make_sky(np, width, sun=None, samples=4):
    """The (width / 2, width, 3) float64 map: each pixel the mean of samples x samples
    directions on a regular grid inside it."""
    height = width // 2
    offsets = (np.arange(samples) + 0.5) / samples
    img = np.empty((height, width, 3))
    cols = np.arange(width)
    for top in range(0, height, ROWS_PER_BAND):
        rows = np.arange(top, min(top + ROWS_PER_BAND, height))
        # (rows, sub-rows, cols, sub-cols) coordinates of every sample of the band.
        v = (rows[:, None, None, None] + offsets[None, :, None, None]) / height
        u = (cols[None, None, :, None] + offsets[None, None, None, :]) / width
        u, v = np.broadcast_arrays(u, v)
        img[rows] = radiance(np, u, v, sun).mean(axis=(1, 3))
    return img


def rgbe_encode(np, rgb):
    """(H, W, 4) uint8 RGBE of (H, W, 3) linear RGB: the shared exponent of the largest
    component, mantissas truncated (Ward's encoding; 0 below 1e-32)."""
    m = rgb.max(axis=-1)
    if m.max() >= 2.0 ** 127:
        raise ValueError("radiance beyond RGBE's range")
    frac, exp = np.frexp(m)  # m = frac * 2**exp, frac in [0.5, 1)
    # A power of two, so the largest component scales exactly to frac * 256 in [128, 256):
    # no flat pixel can read as a run-length marker (2, 2, <128) or (1, 1, 1).
    scale = np.ldexp(1.0, 8 - exp)
    out = np.zeros(rgb.shape[:-1] + (4,), np.uint8)
    visible = m > 1e-32
    out[..., :3] = np.where(visible[..., None],
                            np.clip(np.floor(rgb * scale[..., None]), 0, 255), 0)
    out[..., 3] = np.where(visible, exp + 128, 0)
    return out


def write_hdr(np, path, rgb):
    """A Radiance .hdr of (H, W, 3) `rgb`, flat scanlines, the top row first."""
    h, w = rgb.shape[:2]
    header = f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n".encode("ascii")
    Path(path).write_bytes(header + rgbe_encode(np, rgb).tobytes())


def write_exr(np, path, rgb):
    """An OpenEXR of (H, W, 3) `rgb` as float R, G, B through OpenImageIO."""
    import OpenImageIO as oiio

    h, w = rgb.shape[:2]
    out = oiio.ImageOutput.create(str(path))
    if out is None:
        raise exitcodes.SetupError(f"{path}: {oiio.geterror()}")
    out.open(str(path), oiio.ImageSpec(w, h, 3, oiio.FLOAT))
    ok = out.write_image(np.ascontiguousarray(rgb, np.float32))
    out.close()
    if not ok:
        raise exitcodes.SetupError(f"{path}: {out.geterror()}")


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="make_sky", description=__doc__.split("\n\n", 1)[0],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", type=Path, required=True,
                        help="the file to write: .hdr (Radiance RGBE) or .exr (OpenImageIO)")
    parser.add_argument("--width", type=int, default=512,
                        help="pixels across, even (default 512); the height is half")
    parser.add_argument("--sun-azimuth", type=float, default=135.0,
                        help="degrees: 0 = -Z, 90 = +X, 180 = +Z, 270 = -X (default 135)")
    parser.add_argument("--sun-elevation", type=float, default=35.0,
                        help="degrees above the horizon (default 35)")
    parser.add_argument("--sun-radiance", type=float, default=1e4,
                        help="the sun disk's radiance, times (1, 0.93, 0.82) (default 1e4)")
    parser.add_argument("--no-sun", action="store_true", help="sky, ground and markers only")
    parser.add_argument("--samples", type=int, default=4,
                        help="a samples x samples grid per pixel (default 4)")
    args = parser.parse_args(argv)
    if args.width < 4 or args.width % 2 or args.width > 32768:
        parser.error("--width must be even and in 4..=32768")
    if not 1 <= args.samples <= 16:
        parser.error("--samples must be in 1..=16")
    if not -90.0 <= args.sun_elevation <= 90.0:
        parser.error("--sun-elevation must be in -90..=90 degrees")
    if not 0.0 < args.sun_radiance < 1e6:
        parser.error("--sun-radiance must be in (0, 1e6) (lumis clamps texels above 1e6)")
    kind = args.out.suffix.lower()
    if kind not in (".hdr", ".exr"):
        parser.error(f"--out {args.out}: the extension must be .hdr or .exr")

    import numpy as np

    sun = None
    if not args.no_sun:
        sun = (direction(args.sun_azimuth, args.sun_elevation),
               tuple(args.sun_radiance * c for c in SUN_COLOUR))
    img = make_sky(np, args.width, sun, args.samples)
    try:
        (write_hdr if kind == ".hdr" else write_exr)(np, args.out, img)
    except OSError as e:
        raise exitcodes.SetupError(f"cannot write {args.out}: {e}") from e
    where = ("no sun" if sun is None else
             f"sun at azimuth {args.sun_azimuth:g}, elevation {args.sun_elevation:g} "
             f"(u = {args.sun_azimuth / 360 % 1:.4f}, v = {0.5 - args.sun_elevation / 180:.4f})")
    print(f"wrote {args.out}: {args.width}x{args.width // 2}, {where}")


def cli():
    exitcodes.run(main, prog="make_sky")


if __name__ == "__main__":
    cli()
