"""The images bench_mitsuba compares: RGB out of (and into) EXR files through OpenImageIO, and
their agreement after a least-squares exposure scale (printed beside the error, so that a
scale far from 1 shows; it is not there to hide a difference)."""

from __future__ import annotations

from pathlib import Path

import numpy as np


def read_exr_rgb(path: Path):
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        raise OSError(f"{path}: {oiio.geterror()}")
    try:
        spec = inp.spec()
        names = list(spec.channelnames)
        pixels = inp.read_image(0, 0, 0, spec.nchannels, oiio.FLOAT)
    finally:
        inp.close()
    if pixels is None:
        raise OSError(f"{path}: cannot read pixels")
    return np.stack([pixels[:, :, names.index(c)] for c in "RGB"], axis=-1)


def write_exr_rgb(path: Path, rgb: np.ndarray):
    import OpenImageIO as oiio

    out = oiio.ImageOutput.create(str(path))
    out.open(str(path), oiio.ImageSpec(rgb.shape[1], rgb.shape[0], 3, oiio.FLOAT))
    out.write_image(np.ascontiguousarray(rgb, np.float32))
    out.close()


def agreement(mitsuba: np.ndarray, lumis: np.ndarray):
    """Least-squares exposure scale of Mitsuba's image onto lumis's and the relative RMSE
    after it; both over every pixel and RGB channel."""
    m = mitsuba.astype(np.float64).ravel()
    ref = lumis.astype(np.float64).ravel()
    scale = float(m @ ref / max(m @ m, 1e-300))
    rmse = float(np.sqrt(np.mean((scale * m - ref) ** 2)))
    rms = float(np.sqrt(np.mean(ref ** 2)))
    return {"scale": scale, "rel_rmse": rmse / max(rms, 1e-300),
            "rel_rmse_unscaled": float(np.sqrt(np.mean((m - ref) ** 2))) / max(rms, 1e-300),
            "mean_lumis": float(ref.mean()), "mean_mitsuba": float(m.mean())}
