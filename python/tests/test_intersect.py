"""Ray queries: known answers, bit-identity with `lumis hits`, input layouts, the ray domain,
threads."""

from __future__ import annotations

import math
import threading

import numpy as np
import pytest

import lumis
from lumis import Hits
from conftest import ASSETS, SCENES, bits, cli_hits, random_rays

KNOT = ASSETS / "knot.obj"


@pytest.fixture(scope="module")
def knot():
    return lumis.load(KNOT)


def knot_rays(scene, n=4000, seed=1):
    v = scene.triangles()[:, 1:].reshape(-1, 3)
    lo, hi = v.min(0), v.max(0)
    return random_rays(n, seed, centre=(lo + hi) / 2, radius=float(np.linalg.norm(hi - lo)))


def split(rays):
    return rays[:, 0:3], rays[:, 3:6], rays[:, 6], rays[:, 7]


def test_unit_sphere_known_answers(tmp_path):
    scene = tmp_path / "ball.toml"
    scene.write_text(
        '[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n'
        '[materials.m]\ndiffuse = [0.5, 0.5, 0.5]\n'
        '[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = "m"\n'
    )
    s = lumis.load(scene)
    o = np.array([[0, 0, 5], [0, 0, 5], [0, 0, 0], [3, 0, 0]], np.float32)
    d = np.array([[0, 0, -1], [0, 0, 1], [2, 0, 0], [0, 1, 0]], np.float32)
    h = s.intersect(o, d)
    # From 5 towards the centre: the near side at t = 4, normal +z; away: a miss; from the
    # centre along a direction of length 2: the far side at t = 0.5 (t in units of |d|).
    assert h.t.tolist() == [4.0, math.inf, 0.5, math.inf]
    assert h.prim_id.tolist() == [0, -1, 0, -1]
    assert h.kind.tolist() == [0, -1, 0, -1]
    assert h.normal[0].tolist() == [0.0, 0.0, 1.0]
    assert h.normal[2].tolist() == [1.0, 0.0, 0.0]
    assert h.hit.tolist() == [True, False, True, False]
    # (t_min, t_max]: the near hit at 4 is outside (4, inf), the far one at 6 inside.
    assert s.intersect(o[:1], d[:1], 4.0).t.tolist() == [6.0]
    assert s.intersect(o[:1], d[:1], 0.0, 3.5).t.tolist() == [math.inf]
    assert s.occluded(o, d).tolist() == [True, False, True, False]
    assert s.occluded(o, d, 0.0, np.array([3.5, 1, 1, 1])).tolist() == [False, False, True, False]


@pytest.mark.parametrize("accel", ["sah", "brute", "bsp", "bsmp"])
def test_bit_identical_to_lumis_hits(knot, cli, tmp_path, accel):
    rays = knot_rays(knot).astype(np.float32)
    rays[::7, 6] = 0.5  # some t_min, some t_max
    rays[::11, 7] = 2.0
    want = cli_hits(cli, tmp_path, KNOT, rays, "--accel", accel)
    got = knot.intersect(*split(rays), accel=accel)
    assert np.array_equal(bits(got.rows()), bits(want))
    assert got.hit.mean() > 0.3  # the rays do hit the knot
    blocked = cli_hits(cli, tmp_path, KNOT, rays, "--accel", accel, "--any-hit")
    assert np.array_equal(knot.occluded(*split(rays), accel=accel), blocked[:, 0] != np.inf)


@pytest.mark.parametrize("precision", ["fast", "watertight", "double"])
def test_precision_matches_the_flag(knot, cli, tmp_path, precision):
    rays = knot_rays(knot, 1000, seed=2).astype(np.float32)
    want = cli_hits(cli, tmp_path, KNOT, rays, "--precision", precision)
    got = knot.intersect(*split(rays), precision=precision)
    assert np.array_equal(bits(got.rows()), bits(want))


def test_float64_rays_are_rounded_to_float32_once(knot, cli, tmp_path):
    rays = knot_rays(knot, 2000, seed=3)  # float64, not representable in float32
    want = cli_hits(cli, tmp_path, KNOT, rays.astype(np.float32))
    got = knot.intersect(*split(rays))
    assert np.array_equal(bits(got.rows()), bits(want))


def test_layouts_give_the_same_answers(knot):
    rays = knot_rays(knot, 1500, seed=4).astype(np.float32)
    want = knot.intersect(*split(rays)).rows()
    # Strided views straight into the (N, 8) block, Fortran order, float64, lists.
    o, d = rays[:, 0:3], rays[:, 3:6]
    for args in [
        (o, d),
        (np.asfortranarray(o), np.asfortranarray(d)),
        (o.astype(np.float64), d),
        (o.tolist(), d.tolist()),
    ]:
        assert np.array_equal(bits(knot.intersect(*args).rows()), bits(want))
    # Reversed rows (negative strides) give the reversed answers.
    rev = knot.intersect(o[::-1], d[::-1]).rows()
    assert np.array_equal(bits(rev[::-1]), bits(want))
    # t_min/t_max: a scalar, a float32 array, a float64 array, a 0-d array.
    n = len(rays)
    for t_max in [np.inf, np.full(n, np.inf, np.float32), np.full(n, np.inf), np.array(np.inf)]:
        assert np.array_equal(bits(knot.intersect(o, d, 0, t_max).rows()), bits(want))


def test_empty_batch(knot):
    h = knot.intersect(np.zeros((0, 3)), np.zeros((0, 3)))
    assert len(h) == 0 and h.normal.shape == (0, 3)
    assert knot.occluded(np.zeros((0, 3)), np.zeros((0, 3))).shape == (0,)


def test_bad_rays_raise_naming_the_index(knot, cli, tmp_path):
    rays = knot_rays(knot, 40, seed=5).astype(np.float32)
    rays[17, 3:6] = 0
    with pytest.raises(lumis.RayError) as e:
        knot.intersect(*split(rays))
    message = str(e.value)
    assert message.startswith("ray 17: direction ")
    assert isinstance(e.value, ValueError)
    # The same words as `lumis hits` (which prefixes the file name).
    np.save(tmp_path / "rays.npy", rays)
    p = __import__("conftest").cli_error(
        cli, "hits", KNOT, "--rays", tmp_path / "rays.npy", "--out", tmp_path / "h.npy"
    )
    assert p == f"{tmp_path / 'rays.npy'}: {message}"
    rays[17, 3:6] = 1
    rays[3, 0] = np.nan
    with pytest.raises(lumis.RayError, match=r"^ray 3: origin "):
        knot.occluded(*split(rays))
    with pytest.raises(lumis.RayError, match=r"^ray 0: t_min "):
        knot.intersect(rays[:, 0:3], rays[:, 3:6], np.nan)
    with pytest.raises(ValueError, match="shape"):
        knot.intersect(rays[:, 0:2], rays[:, 3:5])
    with pytest.raises(ValueError, match="40 origins but 39 directions"):
        knot.intersect(rays[:, 0:3], rays[1:, 3:6])
    with pytest.raises(ValueError, match="t_max: 3 values for 40 rays"):
        knot.intersect(rays[:, 0:3], rays[:, 3:6], 0.0, np.ones(3))
    with pytest.raises(ValueError, match="accel"):
        knot.intersect(rays[:, 0:3], rays[:, 3:6], accel="kd")
    with pytest.raises(ValueError, match="precision"):
        knot.intersect(rays[:, 0:3], rays[:, 3:6], precision="exact")


def test_threads_do_not_change_answers_and_callers_run_concurrently(knot):
    rays = knot_rays(knot, 20000, seed=6).astype(np.float32)
    want = knot.intersect(*split(rays), threads=1).rows()
    assert np.array_equal(bits(knot.intersect(*split(rays), threads=2).rows()), bits(want))
    assert np.array_equal(bits(knot.intersect(*split(rays)).rows()), bits(want))
    results = {}
    errors = []

    def work(k):
        try:
            # Different slices, accelerators and thread counts at once.
            sl = slice(k * 1000, k * 1000 + 8000)
            accel = ["sah", "bsp"][k % 2]
            results[k] = (sl, knot.intersect(*split(rays[sl]), accel=accel, threads=k % 3).rows())
        except Exception as e:  # pragma: no cover - reported below
            errors.append(e)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for sl, rows in results.values():
        assert np.array_equal(bits(rows), bits(want[sl]))


def test_intersect_all_known_answers_and_cli_rows(knot, cli, tmp_path):
    ball = tmp_path / "ball.toml"
    ball.write_text(
        '[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n'
        '[materials.m]\ndiffuse = [0.5, 0.5, 0.5]\n'
        '[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = "m"\n'
    )
    s = lumis.load(ball)
    o = np.array([[0, 0, 5], [0, 0, 5], [1, 0, 5]], np.float32)
    d = np.array([[0, 0, -1], [0, 0, 1], [0, 0, -1]], np.float32)
    a = s.intersect_all(o, d)
    # In at 4 and out at 6; no hits; a tangent at x = 1 is one graze at t = 5.
    assert a.ray.tolist() == [0, 0, 2]
    assert a.t.tolist() == [4.0, 6.0, 5.0]
    assert a.graze.tolist() == [False, False, True]
    assert a.normal.tolist() == [[0, 0, 1], [0, 0, -1], [1, 0, 0]]
    # The knot: bit for bit the rows of lumis hits --all.
    rays = knot_rays(knot, 3000, seed=8).astype(np.float32)
    want = cli_hits(cli, tmp_path, KNOT, rays, "--all")
    a = knot.intersect_all(*split(rays))
    rows = np.column_stack([a.ray.astype(np.float32), Hits(*(getattr(a, k) for k in
                           ("t", "prim_id", "obj_id", "u", "v", "normal", "kind",
                                            "inst_id"))).rows(),
                           a.graze.astype(np.float32)])
    assert np.array_equal(bits(rows), bits(want))
    # The first hit of each ray is its nearest hit; a closed knot is crossed an even number
    # of times by every ray that ends outside it.
    near = knot.intersect(*split(rays))
    first = np.unique(a.ray, return_index=True)[1]
    assert np.array_equal(bits(a.t[first]), bits(near.t[a.ray[first]]))
    assert np.array_equal(np.unique(a.ray), np.nonzero(near.hit)[0])
    crossings = np.bincount(a.ray[~a.graze], minlength=len(rays))
    assert (crossings % 2 == 0).all()


def test_default_scene_spheres_and_triangles(cli, tmp_path):
    path = SCENES / "default.toml"
    s = lumis.load(path)
    assert s.spheres().shape[1] == 5 and len(s.spheres()) > 0
    centre = s.spheres()[0, 1:4].astype(np.float64)
    rays = random_rays(3000, 7, centre=centre, radius=4.0).astype(np.float32)
    want = cli_hits(cli, tmp_path, path, rays)
    assert np.array_equal(bits(s.intersect(*split(rays)).rows()), bits(want))
    assert (want[:, 8] == 0).any()  # sphere hits among them
