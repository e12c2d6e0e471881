"""Loading: every format, `-D` overrides as keyword arguments, dicts and strings, the model
options, and errors carrying the message `lumis` prints."""

from __future__ import annotations

import numpy as np
import pytest

import lumis
from conftest import ASSETS, SCENES, cli_error

FILES = [
    SCENES / "default.toml",
    ASSETS / "knot.obj",
    ASSETS / "gltf" / "cube.gltf",
    ASSETS / "gltf" / "cube.glb",
    ASSETS / "gltf" / "cube_embedded.gltf",
]


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_every_format_loads(path):
    s = lumis.load(path)
    assert s.num_primitives > 0 and s.num_objects > 0
    assert s.path == str(path)
    assert len(s.triangles()) + len(s.spheres()) == s.num_primitives


def test_scn_loads():
    # The paper's format, through its scenes beside the checkout (../shared) when present.
    scn = sorted((ASSETS.parents[1] / "shared" / "paper-scenes" / "scenes").glob("*.scn"))
    if not scn:
        pytest.skip("the paper's .scn scenes are not beside the checkout (../shared)")
    s = lumis.load(scn[0])
    assert s.num_primitives > 0


def test_overrides_as_keywords_dicts_and_strings():
    path = SCENES / "default.toml"
    base = lumis.load(path).settings
    s = lumis.load(path, **{"render.spp": 2, "render.width": 64})
    assert (s.settings["spp"], s.settings["width"]) == (2, 64)
    assert s.settings["height"] == base["height"]
    s = lumis.load(path, {"render.spp": 3}, **{"render.spp": 5})
    assert s.settings["spp"] == 5  # keywords come after the dict
    s = lumis.load(path, ["render.spp=4", "render.precision=double"])
    assert (s.settings["spp"], s.settings["precision"]) == (4, "double")
    s = lumis.load(path, **{"render.exposure": np.float32(1.5)})
    assert s.settings["exposure"] == 1.5
    # A string is always a TOML string, also when it looks like a number.
    with pytest.raises(lumis.SceneError, match=r'render\.spp="4"'):
        lumis.load(path, **{"render.spp": "4"})
    # Other formats take render.* keys only.
    s = lumis.load(ASSETS / "knot.obj", **{"render.spp": 3})
    assert s.settings["spp"] == 3
    with pytest.raises(lumis.SceneError, match="camera.fov"):
        lumis.load(ASSETS / "knot.obj", **{"camera.fov": 30})


def test_model_options():
    gltf = ASSETS / "gltf" / "lights_camera.gltf"
    a = lumis.load(gltf)
    b = lumis.load(gltf, auto_camera=True)
    assert a.num_primitives == b.num_primitives
    z = lumis.load(ASSETS / "knot.obj", up="z")
    y = lumis.load(ASSETS / "knot.obj")
    assert not np.array_equal(z.triangles(), y.triangles())  # turned to Y-up
    with pytest.raises(lumis.SceneError, match="glTF files only"):
        lumis.load(SCENES / "default.toml", gltf_scene=0)
    with pytest.raises(ValueError, match="up="):
        lumis.load(ASSETS / "knot.obj", up="x")


@pytest.mark.parametrize(
    "name,text,defines",
    [
        ("missing.toml", None, []),
        ("syntax.toml", "[camera\n", []),
        ("bad_value.toml", "[render]\nspp = -1\n", []),
        ("unknown.xyz", "", []),
        ("spp.toml", None, ["render.spp=abc"]),
        ("spp.toml", None, ['render.spp="abc"']),
        ("spp.toml", None, ["render.nosuchkey=1"]),
        ("spp.toml", None, ["sphere.9.radius=2"]),
    ],
)
def test_errors_carry_the_cli_message(cli, tmp_path, name, text, defines):
    path = tmp_path / name
    if text is not None:
        path.write_text(text)
    if name == "spp.toml":
        path = SCENES / "default.toml"
    flags = [a for d in defines for a in ("-D", d)]
    want = cli_error(cli, "render", path, "-o", tmp_path / "out.exr", "--quiet", *flags)
    with pytest.raises(lumis.SceneError) as e:
        lumis.load(path, defines)
    assert str(e.value) == want
    assert isinstance(e.value, ValueError)


def test_bad_define_syntax():
    with pytest.raises(lumis.SceneError, match="expected KEY=VALUE"):
        lumis.load(SCENES / "default.toml", ["render.spp"])
    with pytest.raises(TypeError, match="scene parameter"):
        lumis.load(SCENES / "default.toml", **{"render.spp": object()})
