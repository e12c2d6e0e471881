"""Renders: the arrays hold exactly the pixels of `lumis render`'s EXR (read back with
OpenImageIO), for a TOML scene (fixed exposure, half RGBA) and an OBJ model (automatic
exposure, float RGBA, every AOV layer), with Blender's channel names, written to files, and
independent of the thread count."""

from __future__ import annotations

import json

import numpy as np
import pytest

import lumis
from conftest import ASSETS, SCENES, run_cli

oiio = pytest.importorskip("OpenImageIO")


def read_exr(path):
    """Every channel of `path` as float32 `(H, W)` planes (half converts exactly)."""
    inp = oiio.ImageInput.open(str(path))
    assert inp, oiio.geterror()
    spec = inp.spec()
    pixels = inp.read_image(0, 0, 0, spec.nchannels, oiio.FLOAT)
    inp.close()
    return {name: pixels[:, :, i] for i, name in enumerate(spec.channelnames)}


def assert_same(image: lumis.Image, exr: dict):
    assert sorted(image) == sorted(exr)
    for name, plane in image.items():
        got = plane.astype(np.float32)
        assert got.shape == exr[name].shape, name
        assert np.array_equal(got.view(np.uint32), exr[name].view(np.uint32)), name


@pytest.mark.parametrize(
    "path,kwargs,flags",
    [
        (SCENES / "default.toml", dict(width=64, height=48, spp=1), []),
        (
            ASSETS / "knot.obj",
            dict(width=40, height=30, spp=2, aovs=["albedo", "position", "uv"], float_rgba=True,
                 seed=7),
            ["--aov", "albedo,position,uv", "--float", "--seed", "7"],
        ),
        (
            ASSETS / "gltf" / "materials.gltf",
            dict(width=32, height=32, spp=1, layout="blender", exposure=0.5, max_depth=2),
            ["--layout", "blender", "--exposure", "0.5", "--max-depth", "2"],
        ),
        (
            SCENES / "default.toml",
            dict(width=48, height=27, spp=1, aovs=["lightpaths", "lights"], float_rgba=True),
            ["--aov", "lightpaths,lights", "--float"],
        ),
    ],
    ids=["toml", "obj-aovs-float", "gltf-blender", "toml-light-paths"],
)
def test_render_equals_the_cli_exr(cli, tmp_path, path, kwargs, flags):
    scene = lumis.load(path)
    image = scene.render(**kwargs)
    size = ["--width", kwargs["width"], "--height", kwargs["height"], "--spp", kwargs["spp"]]
    run_cli(cli, "render", path, "-o", tmp_path / "cli.exr", "--quiet", *size, *flags)
    assert_same(image, read_exr(tmp_path / "cli.exr"))
    rgba = image.rgba()
    assert rgba.dtype == (np.float32 if kwargs.get("float_rgba") else np.float16)
    assert rgba.shape == (kwargs["height"], kwargs["width"], 4)
    assert rgba[..., 3].max() > 0  # something was rendered
    if path.suffix == ".obj":
        assert image.auto_exposure
    else:
        assert not image.auto_exposure


def test_path_writes_the_same_pixels_and_png(cli, tmp_path):
    scene = lumis.load(SCENES / "default.toml", **{"render.spp": 1})
    image = scene.render(48, 32, path=[tmp_path / "py.exr", tmp_path / "py.png"])
    assert_same(image, read_exr(tmp_path / "py.exr"))
    run_cli(cli, "render", SCENES / "default.toml", "-o", tmp_path / "cli.exr", "--png",
            tmp_path / "cli.png", "--quiet", "--width", 48, "--height", 32, "-D",
            "render.spp=1")
    assert_same(image, read_exr(tmp_path / "cli.exr"))
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()


def test_threads_do_not_change_the_image():
    scene = lumis.load(SCENES / "default.toml")
    a = scene.render(40, 24, 2, threads=1)
    b = scene.render(40, 24, 2, threads=2)
    for name in a:
        assert np.array_equal(a[name], b[name], equal_nan=True), name


def test_render_errors():
    scene = lumis.load(SCENES / "default.toml")
    with pytest.raises(ValueError, match="spp"):
        scene.render(8, 8, 0)
    with pytest.raises(ValueError, match="aovs"):
        scene.render(8, 8, 1, aovs=["depth"])
    with pytest.raises(ValueError, match="exposure"):
        scene.render(8, 8, 1, exposure=float("nan"))
    with pytest.raises(ValueError, match="layout"):
        scene.render(8, 8, 1, layout="nuke")


def write_hdr(path, rgb):
    """A flat-RGBE Radiance file of the `(H, W, 3)` float array `rgb`."""
    h, w, _ = rgb.shape
    m = rgb.max(axis=-1)
    e = np.where(m > 1e-32, np.floor(np.log2(np.maximum(m, 1e-32))) + 1, 0)
    scale = np.where(m > 1e-32, 256.0 / np.exp2(e), 0.0)
    out = np.zeros((h, w, 4), np.uint8)
    out[..., :3] = np.clip(rgb * scale[..., None], 0, 255).astype(np.uint8)
    out[..., 3] = np.where(m > 1e-32, e + 128, 0).astype(np.uint8)
    with open(path, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w))
        f.write(out.tobytes())


def test_an_environment_from_defines_renders_as_the_cli(cli, tmp_path):
    """`environment.*` defines reach every format; the light paths add up to RGB."""
    v = np.linspace(0, 1, 16)[:, None, None]
    write_hdr(tmp_path / "sky.hdr", np.broadcast_to(v * [0.2, 0.4, 0.8] + 0.1, (16, 32, 3)))
    path = ASSETS / "knot.obj"
    defines = [f'environment.file="{tmp_path / "sky.hdr"}"', "environment.rotation=45"]
    image = lumis.load(path, defines=defines).render(
        32, 24, 1, aovs=["lightpaths"], float_rgba=True, exposure=0.0
    )
    flags = [x for d in defines for x in ("-D", d)]
    run_cli(cli, "render", path, "-o", tmp_path / "cli.exr", "--quiet", "--width", 32,
            "--height", 24, "--spp", 1, "--aov", "lightpaths", "--float", "--exposure", 0,
            *flags)
    assert_same(image, read_exr(tmp_path / "cli.exr"))
    paths = ["diffuse", "specular", "reflection", "refraction", "emission", "ambient",
             "background"]
    for c in "RGB":
        total = sum(image[f"{p}.{c}"] for p in paths)
        assert np.allclose(total, image[c], rtol=1e-5, atol=1e-6), c
    assert image["background.B"].max() > 0.1  # the sky is seen around the knot


def header(path):
    """The custom string attributes of an EXR, by name."""
    inp = oiio.ImageInput.open(str(path))
    spec = inp.spec()
    inp.close()
    return {a.name: a.value for a in spec.extra_attribs if a.name.startswith("lumis/")}


@pytest.mark.parametrize(
    "path,load,kwargs,flags",
    [
        (SCENES / "default.toml", {"render.max_depth": 3},
         dict(width=40, height=24, spp=2, aovs=["albedo"], exposure=-0.5, seed=3),
         ["-D", "render.max_depth=3", "--width", "40", "--height", "24", "--spp", "2",
          "--aov", "albedo", "--exposure", "-0.5", "--seed", "3"]),
        (ASSETS / "gltf" / "materials.gltf", {},
         dict(width=32, height=32, spp=1, layout="blender", float_rgba=True),
         ["--width", "32", "--height", "32", "--spp", "1", "--layout", "blender", "--float"]),
    ],
    ids=["toml", "gltf"],
)
def test_a_file_render_records_what_the_command_records(cli, tmp_path, path, load, kwargs, flags):
    scene = lumis.load(path, **load)
    image = scene.render(**kwargs, path=tmp_path / "py.exr")
    run_cli(cli, "render", path, "-o", tmp_path / "cli.exr", "--quiet", *flags)
    py, cmd = header(tmp_path / "py.exr"), header(tmp_path / "cli.exr")
    # The same render: the same scene hash, seed and settings record as the command's.
    for name in ("lumis/sceneHash", "lumis/seed", "lumis/settings"):
        assert py[name] == cmd[name], name
    assert image.settings == json.loads(cmd["lumis/settings"])
    # And the command renders Python's file again, byte for byte.
    run_cli(cli, "render", "--from", tmp_path / "py.exr", "-o", tmp_path / "again.exr", "--quiet")
    assert (tmp_path / "again.exr").read_bytes() == (tmp_path / "py.exr").read_bytes()


def test_a_scene_from_arrays_records_no_settings():
    v = np.array([[0, 0, -2], [1, 0, -2], [0, 1, -2]], float)
    image = lumis.Scene.from_arrays(v, np.array([[0, 1, 2]])).render(8, 8, 1)
    assert image.settings is None
