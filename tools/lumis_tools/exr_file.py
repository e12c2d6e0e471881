"""lumis's EXR as OpenImageIO reads it, and the contract of src/output/exr.rs on its layout
and header (see crosscheck_exr's doc); also the writer of the difference EXRs."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

from .idiff import EXIT_FAIL, EXIT_OK, EXIT_WARN, STATUS, ToolError

CHANNELS = ["R", "G", "B", "A", "Z", "N.X", "N.Y", "N.Z", "id.prim", "id.object"]
FLOAT_CHANNELS = ["Z", "N.X", "N.Y", "N.Z", "id.prim", "id.object"]
RGBA = ["R", "G", "B", "A"]


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
    a = attribute(spec, "lumis/sppPerAxis")
    ok = a is not None and a.type == oiio.TypeInt and (spp is None or a.value == spp)
    checks.add("lumis/sppPerAxis (int, spp)", ok, f"{a.value if a is not None else None}")
    # Only with --timing-metadata: by default the same input gives the same bytes.
    a = attribute(spec, "lumis/renderSeconds")
    checks.add("lumis/renderSeconds absent, or float >= 0",
               a is None or (a.type == oiio.TypeFloat and a.value >= 0),
               f"{a.value if a is not None else None}")
    # Rec.709 / sRGB primaries and the D65 white point, as ITU-R BT.709 gives them.
    a = attribute(spec, "chromaticities")
    want = [0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290]
    got = list(np.ravel(a.value)) if a is not None else None
    checks.add("chromaticities = Rec.709, D65",
               got is not None and np.allclose(got, want, rtol=0, atol=1e-6), f"{got}")
    return w2c, w2ndc


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
