"""Shared fixtures of the checkers' own tests: small EXRs written to lumis's contract, so the
reader and the idiff clone are tested on files whose every value is known."""

from __future__ import annotations

import numpy as np
import OpenImageIO as oiio
import pytest

from lumis_tools.exr_file import CHANNELS, FLOAT_CHANNELS


def write_exr(path, channels: dict, formats: dict | None = None, attributes: dict | None = None):
    """Writes `channels` ({name: (H, W) array}) as a scanline ZIP EXR; `formats` gives a
    channel's pixel type ("half" or "float", default float), `attributes` header entries as
    {name: (TypeDesc, value)}."""
    names = list(channels)
    h, w = np.shape(channels[names[0]])
    spec = oiio.ImageSpec(w, h, len(names), oiio.FLOAT)
    spec.channelnames = tuple(names)
    spec.channelformats = tuple(oiio.TypeDesc((formats or {}).get(n, "float")) for n in names)
    spec.attribute("compression", "zip")
    for name, (kind, value) in (attributes or {}).items():
        spec.attribute(name, kind, value)
    out = oiio.ImageOutput.create(str(path))
    assert out is not None, oiio.geterror()
    assert out.open(str(path), spec), out.geterror()
    data = np.stack([np.asarray(channels[n], np.float32) for n in names], axis=-1)
    assert out.write_image(data), out.geterror()
    out.close()
    return path


def contract_channels(width=4, height=3):
    """Every channel lumis writes, all pixels misses (Z inf, N 0, ids -1, black)."""
    px = {n: np.zeros((height, width)) for n in CHANNELS}
    px["Z"][:] = np.inf
    px["id.prim"][:] = -1
    px["id.object"][:] = -1
    return px


def contract_formats(float_rgba=False):
    """The pixel types of the contract: Z, N.*, id.* FLOAT; RGBA HALF (FLOAT with --float)."""
    rgba = "float" if float_rgba else "half"
    return {n: ("float" if n in FLOAT_CHANNELS else rgba) for n in CHANNELS}


@pytest.fixture
def exr_path(tmp_path):
    """A factory: exr_path(name) -> a path in the test's temporary folder."""
    return lambda name: tmp_path / name
