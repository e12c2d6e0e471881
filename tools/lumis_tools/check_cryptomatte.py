#!/usr/bin/env python3
"""Renders scenes with `--cryptomatte --transparent` and checks the Cryptomatte layers with an
independent reader (lumis_tools.cryptomatte, written from the specification; also the
cryptomatte-api package when it is installed):

- metadata: hash MurmurHash3_32, conversion uint32_to_float32, key = 7 hex digits of the type
  name's hash, every manifest entry = the id of its name;
- names: the CryptoObject manifest is exactly the scene's object names, CryptoMaterial its
  objects' material names (read from the scene files, lumis_tools.cryptomatte_names); every id
  a pixel holds is in the manifest;
- ranks: coverage non-increasing, empty ranks id 0 coverage 0;
- coverage: per pixel, the mattes of all names sum to alpha (the A channel, float) where fewer
  than `levels` ranks are used (nothing was dropped), and to no more than alpha elsewhere;
- anti-aliasing: some pixels are shared by two objects, each with coverage in (0, 1);
- `--layout blender`: ViewLayer.CryptoObject / ViewLayer.CryptoMaterial hold the same ranks.

    tools/check_cryptomatte.py [SCENE ...] [--size 160x90] [--spp 3] [--lumis PATH]

Exit 0 when every check passes, 1 when one fails, 2 when nothing could be checked."""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

from . import REPO, exitcodes, lumis

TOLERANCE = 1e-6  # float32 sums of a few coverages k/n
TYPES = ("CryptoObject", "CryptoMaterial")
# The default scenes, and whether objects overlap in the image (so edges must be shared).
DEFAULT_SCENES = {"scenes/default.toml": True, "assets/illum_modes.obj": False,
                  "assets/gltf/materials.gltf": False}


def obj_in_toml(tmp: Path) -> Path:
    """A TOML scene placing an OBJ with its MTL materials (names `modes/illumN`)."""
    scene = tmp / "obj_in_toml.toml"
    scene.write_text(f'[[mesh]]\nname = "modes"\nfile = "{REPO / "assets" / "illum_modes.obj"}"\n')
    return scene


class Report:
    """Named pass/fail results, printed as they come."""

    def __init__(self, quiet=False):
        self.failed, self.quiet = [], quiet

    def add(self, what, ok, detail=""):
        if not ok:
            self.failed.append(what)
        if not ok or not self.quiet:
            print(f"  {'ok  ' if ok else 'FAIL'} {what}" + (f": {detail}" if detail else ""))
        return ok


def render(scene, out, args, *extra):
    w, h = args.size
    lumis.run(["render", scene, "-o", out, "--width", w, "--height", h, "--spp", args.spp,
               "--cryptomatte", "--transparent", "--float", "--quiet", *extra], "lumis render")


def check_type(t, alpha, expected, r: Report):
    """The checks of one Cryptomatte type against alpha and the expected names."""
    import numpy as np

    r.add(f"{t.name} metadata", not t.problems(), "; ".join(t.problems()))
    names = set(t.manifest or {})
    r.add(f"{t.name} names = scene's", names == expected,
          f"manifest {sorted(names)}, scene {sorted(expected)}")
    known = np.array(sorted({int(h, 16) for h in (t.manifest or {}).values()}), np.uint32)
    used = t.coverage > 0
    unknown = used & ~np.isin(t.ids, known)
    r.add(f"{t.name} every id in the manifest", not unknown.any(),
          f"{int(unknown.sum())} ranks with unknown ids")
    empty = ~used
    r.add(f"{t.name} empty ranks are id 0", not (empty & (t.ids != 0)).any()
          and (t.coverage >= 0).all())
    r.add(f"{t.name} ranks by coverage", (np.diff(t.coverage, axis=-1) <= 0).all())
    total = sum(t.mattes().values()) if names else np.zeros_like(alpha)
    complete = t.coverage[..., -1] == 0
    err = np.abs(total - alpha)[complete]
    r.add(f"{t.name} mattes sum to alpha", err.size > 0 and err.max() <= TOLERANCE,
          f"{int(complete.sum())} pixels with < {t.levels} ids, max |sum - A| "
          f"{err.max() if err.size else float('nan'):.2e}")
    over = (total - alpha)[~complete]
    r.add(f"{t.name} full pixels sum to <= alpha", (over <= TOLERANCE).all(),
          f"{int((~complete).sum())} pixels with all {t.levels} ranks used")
    return total


def edges(t, alpha):
    """(pixels where two names each cover a fraction in (0, 1), pixels where one name covers
    a fraction and the rest is background)."""
    fractional = (t.coverage > 0) & (t.coverage < 1)
    shared = int((fractional.sum(axis=-1) >= 2).sum())
    alone = (fractional.sum(axis=-1) == 1) & (t.coverage[..., 1] == 0) & (alpha < 1)
    return shared, int(alone.sum())


def check_api(path, ours, r: Report):
    """The same mattes through the cryptomatte-api package, when installed."""
    try:
        import cryptomatte_api
    except ImportError:
        print("  skip cryptomatte-api: not installed (pip install cryptomatte-api)")
        return
    import numpy as np

    for cmatte in cryptomatte_api.Cryptomatte.load(str(path)):
        name = cmatte.metadata().name()
        mine = ours.types[name]
        theirs = cmatte.masks()
        worst = max((float(np.abs(theirs[n] - m).max()) for n, m in mine.mattes().items()
                     if n in theirs), default=0.0)
        r.add(f"{name} = cryptomatte-api's", set(theirs) == set(mine.manifest or {})
              and worst <= TOLERANCE, f"{len(theirs)} mattes, max difference {worst:.1e}")


def check_scene(scene: Path, overlapping: bool, args, tmp: Path, r: Report):
    import numpy as np

    from . import cryptomatte as cm
    from .cryptomatte_names import expected_names

    expected = expected_names(scene)
    out = tmp / f"{scene.stem}.exr"
    render(scene, out, args)
    f = cm.read(out)
    r.add("types", set(f.types) == set(TYPES), f"{sorted(f.types)}")
    alpha = f.pixels["A"]
    for name in TYPES:
        if name in f.types:
            check_type(f.types[name], alpha, expected[name], r)
    obj = f.types.get("CryptoObject")
    if obj is not None:
        shared, alone = edges(obj, alpha)
        if overlapping:
            r.add("anti-aliased edges shared by two objects", shared > 0, f"{shared} pixels")
        r.add("anti-aliased edges against the background", alone > 0, f"{alone} pixels")
        interior = int(((obj.coverage[..., 0] == 1) & (alpha == 1)).sum())
        r.add("interior pixels: one id, coverage 1", interior > 0, f"{interior} pixels")
    check_api(out, f, r)
    blender = tmp / f"{scene.stem}.blender.exr"
    render(scene, blender, args, "--layout", "blender")
    b = cm.read(blender)
    for name in TYPES:
        ours, theirs = f.types.get(name), b.types.get(f"ViewLayer.{name}")
        same = (ours is not None and theirs is not None and theirs.problems() == []
                and np.array_equal(ours.ids, theirs.ids)
                and np.array_equal(ours.coverage, theirs.coverage)
                and ours.manifest == theirs.manifest)
        r.add(f"--layout blender: ViewLayer.{name} = {name}", same)


def size(text):
    w, _, h = text.partition("x")
    return int(w), int(h)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scenes", nargs="*", type=Path,
                    help="scene files (default: the default scene, an OBJ, a glTF and an OBJ "
                    "placed by a TOML scene); edges shared by two objects are required only "
                    "of the default scene")
    ap.add_argument("--size", type=size, default=(160, 90), metavar="WxH")
    ap.add_argument("--spp", type=int, default=3, help="samples per axis (default 3)")
    ap.add_argument("--quiet", action="store_true", help="print failures only")
    lumis.add_argument(ap)
    args = ap.parse_args(argv)
    lumis.use(args.lumis)
    lumis.binary()  # a missing or stale binary is a setup error, before any scene
    from .cryptomatte import CryptomatteError
    from .cryptomatte_names import UnsupportedScene

    r = Report(args.quiet)
    with tempfile.TemporaryDirectory(prefix="lumis-cryptomatte-") as tmp:
        tmp = Path(tmp)
        scenes = ({s: False for s in args.scenes} if args.scenes else
                  {REPO / s: o for s, o in DEFAULT_SCENES.items()} | {obj_in_toml(tmp): False})
        for scene, overlapping in scenes.items():
            print(f"{scene.name}:")
            try:
                check_scene(scene, overlapping, args, tmp, r)
            except UnsupportedScene as e:
                raise exitcodes.SetupError(str(e)) from e
            except CryptomatteError as e:  # lumis wrote something the reader refuses
                r.add("readable Cryptomatte", False, str(e))
    if r.failed:
        print(f"\nFAILED: {len(r.failed)} checks")
        return exitcodes.FAILED
    print(f"\nall Cryptomatte checks passed ({len(scenes)} scenes)")
    return exitcodes.OK


def cli():
    exitcodes.run(main, prog="check_cryptomatte")


if __name__ == "__main__":
    cli()
