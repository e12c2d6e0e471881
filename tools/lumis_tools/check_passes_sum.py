#!/usr/bin/env python3
"""Checks that lumis's light-path passes (`--aov lightpaths`) add up to the beauty and its
per-light passes (`--aov lights`) to the direct light, on every pixel, reading the EXR with
OpenImageIO (not lumis's own reader):

    R, G, B = diffuse + specular + reflection + refraction + emission + ambient + background
    diffuse + specular = sum over the scene's lights of light.<name>

in either channel layout (lumis's, or `--layout blender`: ViewLayer.Combined.R/G/B, DiffDir,
GlossDir, GlossInd, TransInd, Emit, Ambient, Env, Combined_<name>).

    tools/check_passes_sum.py [EXR ...] [--size 96x72] [--spp 2] [--keep DIR] [--lumis PATH]

With files, it checks those. Without, it renders with `--aov lightpaths,lights --float`, in
both layouts: lumis's built-in default scene (`lumis render` with no scene: glass, a mirror,
Phong spheres, an emissive bead, two lights, depth of field) and tools/scenes/glass_mirror.toml
(a glass sphere in front of a mirror wall, a glossy sphere, an emissive bead, two named lights
"key" and "fill", an environment map written by this tool), and the latter once more without
--float (a HALF beauty). For its own renders it also checks that every pass is FLOAT, that each
pass and light layer is non-zero somewhere (so that no term of a sum goes untested) and that
the light layers are the scene's lights (by name; unnamed lights are light<index>).

Tolerance, per pixel and channel: |sum of the parts - total| <= rel x magnitude + 1e-6, with
magnitude = max(sum of |parts|, |total|) and rel = max(1e-5, 2 (samples + 32) 2^-24) (samples:
the header's lumis/spp, else 64) plus 2^-11 for a HALF beauty (and again for HALF passes).
lumis adds each sample's terms and then the pixel's samples in float32, for the beauty and
for each pass separately, in different orders: the bound for a float sum of n terms is
(n - 1) 2^-24 of the terms' magnitude, so 1e-5 (170 ulps) is 5x that bound at 16 samples; a
missing or doubled term is 1e-3 of the pixel or more. A HALF beauty is rounded once more, by
at most 2^-11 of its value. 1e-6 absolute covers pixels whose every term is ~0, and is far
below an 8-bit step (3e-4 linear). NaN or infinite values fail. lumis's own statement of what
may differ: crates/core/src/integrator/paths.rs (float order, (a + b) x against a x + b x,
samples capped at 1e30 in the beauty only).

Reported per file: pixels checked, the largest absolute and relative difference of each sum,
the pixels outside the tolerance and the worst one. Exit 0 when every file passes, 1 when a
sum is off, 2 when nothing could be checked (a file without the pass layers, lumis failed)."""

from __future__ import annotations

import argparse
import shutil
import tempfile
import tomllib
from pathlib import Path

from . import REPO, TOOLS, exitcodes
from . import lumis as lumis_run
from .sizes import wxh

SCENE = TOOLS / "scenes" / "glass_mirror.toml"
DEFAULT_SCENE = REPO / "scenes" / "default.toml"  # what `lumis render` without a scene renders
DEFAULT_SAMPLES = 64  # for a file without lumis/spp: a generous sample count


def parse_args(argv=None):
    p = argparse.ArgumentParser(
        description="Light-path passes of lumis EXRs summed against the beauty.",
        epilog="Method:\n" + "\n".join("  " + line for line in __doc__.splitlines()),
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("exr", nargs="*", type=Path,
                   help="EXR files to check (default: render the test scenes)")
    p.add_argument("--size", default="96x72", metavar="WxH",
                   help="size of the test renders; default 96x72")
    p.add_argument("--spp", type=int, default=2,
                   help="samples per pixel PER AXIS of the test renders; default 2")
    p.add_argument("--keep", type=Path, metavar="DIR",
                   help="write the test renders (and the scene, sky.hdr) here")
    lumis_run.add_argument(p)
    args = p.parse_args(argv)
    args.width, args.height = wxh(p, "--size", args.size, "96x72")
    if args.spp < 1:
        p.error("--spp must be at least 1")
    return args


def scene_lights(scene: Path):
    """The [[light]] names of a TOML scene as lumis names them: `name`, else light<index>."""
    doc = tomllib.loads(scene.read_text())
    return [l.get("name", f"light{i}") for i, l in enumerate(doc.get("light", []))]


def render_all(args, folder: Path):
    """Renders the test scenes; returns [(exr path, expected light names)]."""
    from .envmap import orientation_map, write_hdr

    scene = folder / SCENE.name
    shutil.copyfile(SCENE, scene)
    write_hdr(folder / "sky.hdr", orientation_map(256, 128))
    runs = [("default", None, "lumis", True), ("default", None, "blender", True),
            ("glass_mirror", scene, "lumis", True), ("glass_mirror", scene, "blender", True),
            ("glass_mirror", scene, "lumis", False)]
    out = []
    for name, path, layout, float_rgba in runs:
        exr = folder / f"{name}_{layout}{'' if float_rgba else '_half'}.exr"
        cmd = ["render", *([path] if path else []), "-o", exr, "--quiet",
               "--width", args.width, "--height", args.height, "--spp", args.spp,
               "--aov", "lightpaths,lights", "--layout", layout,
               *(["--float"] if float_rgba else [])]
        lumis_run.run(cmd, f"lumis render ({name}, {layout})")
        out.append((exr, scene_lights(path or DEFAULT_SCENE)))
    return out


def check_file(path: Path, expected_lights=None):
    """Reads `path` with OpenImageIO and runs both sums; prints one block; True when it passes.
    `expected_lights`: the light names the file must have layers for (our own renders)."""
    from .exr_file import attribute, read_exr
    from .pass_sum import LayerError, check_channels

    exr = read_exr(path)
    a = attribute(exr.spec, "lumis/spp")
    samples = int(a.value) if a is not None else DEFAULT_SAMPLES
    try:
        layers, passes, lights, (rel, abs_tol) = check_channels(exr.pixels, exr.formats, samples)
    except LayerError as e:
        raise exitcodes.SetupError(f"{path}: {e}") from e
    beauty_type = exr.formats[layers.beauty[0]]
    print(f"{path.name}: {layers.layout} layout, beauty {beauty_type}, {samples} samples per "
          f"pixel; tolerance {rel:.3g} x magnitude + {abs_tol:g}")
    ok = True
    rows = [("passes = beauty", passes)]
    if lights is not None:
        rows.append((f"{len(layers.lights)} lights = diffuse + specular", lights))
    else:
        print("  no light layers (rendered without --aov lights): per-light sum not checked")
        ok = expected_lights is None
    for what, c in rows:
        verdict = "ok" if c.ok else "FAIL"
        ok &= c.ok
        print(f"  {what:<34} {c.pixels} pixels, max abs {c.max_abs:.3g}, max rel "
              f"{c.max_rel:.3g}, {c.bad} outside the tolerance, {c.nonfinite} not finite: "
              f"{verdict}")
        if not c.ok:
            print(f"    worst pixel (x {c.worst[0]}, y {c.worst[1]}): {c.worst_detail}")
    if expected_lights is not None:
        pass_names = [n for ch in [*layers.passes.values(), *layers.lights.values()] for n in ch]
        not_float = [n for n in pass_names if exr.formats[n] != "float"]
        if not_float:
            ok = False
            print(f"  FAIL: pass channels not FLOAT: {', '.join(not_float)}")
        # A pass that is 0 everywhere would make its share of the sum vacuous: the test
        # scenes are built so that every pass and light shows somewhere.
        layer_channels = {**layers.passes, **{f"light {k}": v for k, v in layers.lights.items()}}
        empty = [n for n, ch in layer_channels.items()
                 if not any((exr.pixels[c] != 0).any() for c in ch)]
        if empty:
            ok = False
            print(f"  FAIL: layers 0 on every pixel (nothing tested): {', '.join(empty)}")
        if sorted(layers.lights) != sorted(expected_lights):
            ok = False
            print(f"  FAIL: light layers {sorted(layers.lights)}, the scene's lights "
                  f"{sorted(expected_lights)}")
    return ok


def main(argv=None):
    args = parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="check-passes-sum-") as tmp:
        if args.exr:
            files = [(p, None) for p in args.exr]
        else:
            lumis_run.use(args.lumis)
            folder = (args.keep or Path(tmp)).resolve()
            folder.mkdir(parents=True, exist_ok=True)
            files = render_all(args, folder)
        failed = [p.name for p, lights in files if not check_file(p, lights)]
    if failed:
        print(f"FAIL: {', '.join(failed)}")
        return exitcodes.FAILED
    print(f"all {len(files)} files: the passes sum to the beauty"
          + (" and the lights to the direct light" if not args.exr else ""))
    return exitcodes.OK


def cli():
    exitcodes.run(main, setup_errors=(OSError,))


if __name__ == "__main__":
    cli()
