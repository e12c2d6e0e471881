"""The scene bench_mitsuba gives both engines (lumis_tools.mitsuba_scene): lumis's vertical
field of view reaches Mitsuba as the same angle on its y axis, with the same scaled camera."""

from __future__ import annotations

import tomllib

import pytest

from lumis_tools import mitsuba_scene as ms


class FakeTransform:
    """Stands in for mi.ScalarTransform4f: records the look_at it is asked for."""

    def look_at(self, origin, target, up):
        self.args = {"origin": tuple(origin), "target": tuple(target), "up": tuple(up)}
        return self


class FakeMitsuba:
    ScalarTransform4f = FakeTransform


@pytest.fixture
def scene(tmp_path):
    model = tmp_path / "tri.m"
    model.write_text("Vertex 1 0 0.05 0\nVertex 2 0.1 0.05 0\nVertex 3 0 0.15 0\nFace 1 1 2 3\n")
    k = 10.0
    n = ms.prepare_scene(model, tmp_path, k)
    toml = tomllib.loads((tmp_path / "scene.toml").read_text())
    mitsuba = ms.mitsuba_scene_dict(FakeMitsuba, tmp_path, 320, 180, 2, k)
    return n, k, toml, mitsuba


def test_vertical_fov_is_mitsubas_y_axis_fov(scene):
    _, _, toml, mitsuba = scene
    sensor = mitsuba["sensor"]
    # lumis's `fov` is vertical; Mitsuba's is along fov_axis, which defaults to x.
    assert toml["camera"]["fov"] == 40.0
    assert sensor["fov"] == toml["camera"]["fov"]
    assert sensor["fov_axis"] == "y"
    assert (sensor["film"]["width"], sensor["film"]["height"]) == (320, 180)


def test_same_scaled_camera_light_and_samples(scene):
    n, k, toml, mitsuba = scene
    assert n == 1
    look = mitsuba["sensor"]["to_world"].args
    assert look["origin"] == tuple(toml["camera"]["position"]) == \
        pytest.approx((0.0, 1.6, 4.2))  # CAMERA_POSITION x 10
    assert look["target"] == tuple(toml["camera"]["look_at"])
    assert look["up"] == tuple(toml["camera"]["up"]) == (0.0, 1.0, 0.0)
    light = toml["light"][0]
    assert tuple(light["position"]) == mitsuba["light"]["position"]
    # Intensity by k^2 in both, so the image does not change with the scale.
    assert light["intensity"] == mitsuba["light"]["intensity"]["value"] == \
        pytest.approx(ms.LIGHT_INTENSITY * k * k)
    # lumis's --spp N is N x N strata: Mitsuba gets N^2 samples.
    assert mitsuba["sensor"]["sampler"]["sample_count"] == 4
    assert toml["render"]["ambient"] == [0.0, 0.0, 0.0]  # no counterpart in Mitsuba
