"""check_env_mitsuba's helpers (lumis_tools.envmap, lumis_tools.env_mitsuba), without Mitsuba
or the lumis binary: the direction <-> uv convention on hand-derived directions, the rotation's
sense, the RGBE bytes, Mitsuba's bilinear rule, the reference picture, the measures and the
scene texts both engines get."""

from __future__ import annotations

import tomllib
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from lumis_tools import env_mitsuba as em
from lumis_tools import envmap


@pytest.mark.parametrize("d, u, v", [
    # u = atan2(x, -z) / 2pi wrapped to [0, 1), v = acos(y) / pi, worked out by hand.
    ((0.0, 0.0, -1.0), 0.0, 0.5),   # atan2(0, 1) = 0
    ((1.0, 0.0, 0.0), 0.25, 0.5),   # atan2(1, 0) = pi/2
    ((0.0, 0.0, 1.0), 0.5, 0.5),    # atan2(0, -1) = pi
    ((-1.0, 0.0, 0.0), 0.75, 0.5),  # atan2(-1, 0) = -pi/2, wrapped
    ((0.0, 1.0, 0.0), None, 0.0),   # the top row (u arbitrary at the pole)
    ((0.0, -1.0, 0.0), None, 1.0),
    # 45 degrees up, halfway from -Z to +X: u = 1/8, v = 1/4.
    ((0.5, np.sqrt(0.5), -0.5), 0.125, 0.25),
])
def test_direction_to_uv_by_hand(d, u, v):
    gu, gv = envmap.direction_to_uv(np.array(d))
    if u is not None:
        assert gu == pytest.approx(u, abs=1e-12)
        np.testing.assert_allclose(envmap.uv_to_direction(u, v), d, atol=1e-12)
    assert gv == pytest.approx(v, abs=1e-12)


def test_rotation_turns_the_map_as_mitsubas_to_world():
    # rotate(y, 90) takes the map's -Z to world -X: a world ray along -X sees u = 0.
    u = envmap.direction_to_uv(envmap.world_to_map([-1.0, 0.0, 0.0], 90.0))[0]
    assert min(u, 1.0 - u) == pytest.approx(0.0, abs=1e-12)  # 0 or, rounded, just below 1
    # ... and the map's +Z (u = 1/2) to world +X.
    np.testing.assert_allclose(envmap.world_to_map([1.0, 0.0, 0.0], 90.0), [0, 0, 1], atol=1e-12)
    # Right-handed: R_y(90) x = -z (x -> -z, z -> x).
    np.testing.assert_allclose(envmap.rotation_y(90.0) @ [1.0, 0.0, 0.0], [0, 0, -1],
                               atol=1e-12)


def test_rgbe_bytes_by_hand(tmp_path):
    # 1.0 = 0.5 x 2^1: mantissa 128, exponent 129. (0.5, 0.25, 0): 0.5 = 0.5 x 2^0.
    px = envmap.rgbe_encode(np.array([[[1.0, 1.0, 1.0], [0.5, 0.25, 0.0]]]))
    assert px.tolist() == [[[128, 128, 128, 129], [128, 64, 0, 128]]]
    np.testing.assert_array_equal(envmap.rgbe_decode(px), [[[1, 1, 1], [0.5, 0.25, 0]]])
    assert envmap.rgbe_encode(np.zeros((1, 1, 3))).tolist() == [[[0, 0, 0, 0]]]
    img = np.random.default_rng(0).random((3, 9, 3)) * 5 + 0.01
    envmap.write_hdr(tmp_path / "x.hdr", img)
    data = (tmp_path / "x.hdr").read_bytes()
    assert data.startswith(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 3 +X 9\n")
    back = envmap.read_hdr(tmp_path / "x.hdr")
    # Truncated 8-bit mantissas: within 1/128 of the pixel's largest channel, never above.
    assert (back <= img).all()
    assert (img - back <= img.max(axis=-1, keepdims=True) / 128).all()


def test_mitsubas_bilinear_rule():
    img = np.arange(4 * 3, dtype=np.float64).reshape(3, 4)[..., None].repeat(3, axis=-1)
    at = lambda u, v: envmap.lookup_bilinear(img, u, v)[0]  # noqa: E731
    assert at(0.125, 0.0) == 0.0  # column 0's centre, the top row at the pole
    assert at(0.375, 0.5) == 5.0  # column 1, the middle row at v = 1 / (H - 1) = 0.5
    assert at(0.875, 1.0) == 11.0  # the bottom row at the other pole
    assert at(0.0, 0.0) == 1.5  # halfway between the last column (3) and the first (0)
    # Between columns 0 and 1 and rows 0 and 1: the mean of 0, 1, 4 and 5.
    assert at(0.25, 0.25) == pytest.approx(2.5)


def test_orientation_map_is_neither_mirror_nor_quarter_turn_symmetric():
    img = envmap.orientation_map(64, 32)
    rms = np.sqrt(np.mean(img ** 2))
    mirrored = img[:, ::-1]  # u -> 1 - u
    quarter = np.roll(img, 16, axis=1)
    assert np.sqrt(np.mean((mirrored - img) ** 2)) > 0.3 * rms
    assert np.sqrt(np.mean((quarter - img) ** 2)) > 0.3 * rms
    assert img.min() > 0.0 and np.isfinite(img).all()


def test_camera_rays_point_where_the_camera_looks():
    eye, d = em.camera_rays(9, 9, 1)
    centre = np.subtract(em.CAMERA_LOOK_AT, em.CAMERA_POSITION)
    np.testing.assert_allclose(d[4, 4, 0], centre / np.linalg.norm(centre), atol=1e-12)
    assert d[0, 0, 0, 0] < 0 and d[0, 0, 0, 1] > d[4, 4, 0, 1]  # top left: left and up
    np.testing.assert_allclose(np.linalg.norm(d, axis=-1), 1.0)


def test_reference_centre_pixel_sees_the_map_straight_back():
    # The centre ray meets the sphere head on and comes straight back: the pixel shows the
    # map towards the camera, turned by the case's rotation and scaled by its intensity.
    env = envmap.orientation_map(64, 32)
    back = np.subtract(em.CAMERA_POSITION, em.CAMERA_LOOK_AT)
    back /= np.linalg.norm(back)
    for rot, k in ((0.0, 1.0), (90.0, 2.0)):
        img, cov = em.reference_image(env, em.Case("c", "sky.hdr", rot, k), 9, 9, 1)
        u, v = envmap.direction_to_uv(envmap.world_to_map(back, rot))
        np.testing.assert_allclose(img[4, 4], k * envmap.lookup_bilinear(env, u, v), rtol=1e-9)
        assert cov[4, 4] == 1.0 and cov[0, 0] == 0.0  # sphere in the middle, sky in a corner


def test_measures_by_hand():
    ref = np.random.default_rng(2).random((4, 5, 3)) + 0.1
    assert em.rmse(ref, ref) == 0.0
    a = em.compare(0.5 * ref, ref)  # lumis half as bright: scale 2, then no error
    assert a.scale == pytest.approx(2.0, rel=1e-12)
    assert a.rel_rmse == pytest.approx(0.0, abs=1e-12)
    assert a.rel_rmse_unscaled == pytest.approx(0.5, rel=1e-12)
    ones = np.ones((2, 2, 3))
    dark = ones.copy()
    dark[0, 0] = 0.0
    assert em.exposure_scale(ones, ones) == 1.0
    assert em.rmse(dark, ones) == pytest.approx(0.5)  # sqrt(3 / 12)
    cov = np.array([[1.0, 0.0], [0.5, 1.0]])
    b = em.compare(ones, dark, cov)  # the dark pixel is on the sphere
    assert b.scale == pytest.approx(0.75)
    assert set(b.regions) == {"sphere", "background", "rim"}
    assert b.regions["sphere"] > b.regions["background"]


def test_lumis_scene_and_flags_for_each_way_of_setting_the_map(tmp_path):
    by_via = {c.via: c for c in em.CASES}
    assert set(by_via) == {"toml", "flags", "define"}
    doc = tomllib.loads(em.lumis_scene_toml(em.Case("r", "sky.hdr", 90.0, 2.0)))
    assert doc["environment"] == {"file": "sky.hdr", "rotation": 90.0, "intensity": 2.0}
    assert doc["render"]["ambient"] == [0.0, 0.0, 0.0] and "light" not in doc
    mirror = doc["materials"]["mirror"]
    assert mirror == {"diffuse": [0.0] * 3, "specular": [0.0] * 3, "reflectivity": 1.0}
    assert doc["camera"]["fov"] == em.CAMERA_FOV_DEG
    assert em.lumis_flags(em.CASES[0], tmp_path) == []
    flags = by_via["flags"]
    assert "environment" not in tomllib.loads(em.lumis_scene_toml(flags))
    assert em.lumis_flags(flags, tmp_path) == [
        "--env", str(tmp_path / flags.env), f"--env-rotation={flags.rotation!r}",
        f"--env-intensity={flags.intensity!r}"]
    define = by_via["define"]
    assert tomllib.loads(em.lumis_scene_toml(define))["environment"]["rotation"] == 0.0
    assert em.lumis_flags(define, tmp_path) == ["-D", f"environment.rotation={define.rotation!r}"]


def test_mitsuba_scene_is_the_same_picture(tmp_path):
    case = em.Case("r", "sky.exr", -30.0, 2.0)
    root = ET.fromstring(em.mitsuba_scene_xml(case, tmp_path, 96, 64, 4, seed=3))
    integrator = root.find("integrator")
    assert integrator.get("type") == "path"
    assert integrator.find("integer").attrib == {"name": "max_depth", "value": "3"}
    sensor = root.find("sensor")
    assert sensor.find("float[@name='fov']").get("value") == repr(em.CAMERA_FOV_DEG)
    assert sensor.find("string[@name='fov_axis']").get("value") == "y"
    assert sensor.find("sampler/integer[@name='sample_count']").get("value") == "16"
    assert sensor.find("film/integer[@name='width']").get("value") == "96"
    assert sensor.find("film/rfilter").get("type") == "box"
    assert root.find("shape/bsdf").get("type") == "conductor"
    assert root.find("shape/bsdf/string").attrib == {"name": "material", "value": "none"}
    emitter = root.find("emitter")
    assert emitter.get("type") == "envmap"
    assert emitter.find("string").get("value") == str(tmp_path / "sky.exr")
    assert emitter.find("float[@name='scale']").get("value") == "2.0"
    assert [t.tag for t in emitter.find("transform")] == ["rotate"]
    assert emitter.find("transform/rotate").attrib == {"y": "1", "angle": "-30.0"}
    mirrored = ET.fromstring(em.mitsuba_scene_xml(em.Case("m", "sky.hdr", 0.0, mirrored=True),
                                                  tmp_path, 8, 8, 1))
    assert [t.tag for t in mirrored.find("emitter/transform")] == ["scale", "rotate"]


def test_controls_are_wrong_on_purpose():
    names = {c.name for c in em.CASES}
    assert len(names) == len(em.CASES)
    env = envmap.orientation_map(128, 64)
    for lumis_case, wrong in em.CONTROLS:
        assert lumis_case in names
        right = next(c for c in em.CASES if c.name == lumis_case)
        a, cov = em.reference_image(env, right, 24, 24, 2)
        b, _ = em.reference_image(env, wrong, 24, 24, 2)
        assert em.compare(a, b, cov).rel_rmse > 0.15, wrong.name  # 5x check_env's 3%
