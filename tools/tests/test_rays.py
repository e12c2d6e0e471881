"""The seeded ray sets (lumis_tools.rays): the same seed gives the same rays bit for bit, the
first rays are the ones every earlier version generated (so the benchmarks' and the reports'
figures stay comparable), and each set has the geometry its name promises."""

from __future__ import annotations

import numpy as np
import pytest

from lumis_tools import rays as R
from lumis_tools.geometry import Geometry
from lumis_tools.oracle import Oracle

LO, HI = np.zeros(3), np.ones(3)


def two_triangles_and_a_sphere():
    """A unit square of two triangles in z = 0 (sharing the diagonal) and a sphere above."""
    g = Geometry()
    g.add_triangles(np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                              [[1, 0, 0], [1, 1, 0], [0, 1, 0]]], np.float64))
    g.add_sphere((0.5, 0.5, 1.0), 0.25)
    return g


def crosscheck_sets(seed):
    """The five sets in crosscheck_hits's order, from one generator."""
    g = two_triangles_and_a_sphere()
    rng = np.random.default_rng(seed)
    return [R.incoherent(g, 50, rng), R.camera(g, 50), R.grazing(g, 50, rng),
            R.leaving_surfaces(g, Oracle(g), 50, rng), *R.edges_and_vertices(g, 50, rng)]


def test_same_seed_same_rays_bit_for_bit():
    for a, b in zip(crosscheck_sets(1), crosscheck_sets(1)):
        assert a.dtype == b.dtype and a.tobytes() == b.tobytes()
    assert R.bench_incoherent(LO, HI, 500, 3).tobytes() == \
        R.bench_incoherent(LO, HI, 500, 3).tobytes()
    assert R.bench_incoherent(LO, HI, 500, 3).tobytes() != \
        R.bench_incoherent(LO, HI, 500, 4).tobytes()
    assert crosscheck_sets(1)[0].tobytes() != crosscheck_sets(2)[0].tobytes()


def test_first_rays_are_the_historical_ones():
    # Printed by the version before the package (tools/bench_embree.py, tools/lumis_tools/rays.py);
    # a change of seed handling or of the order of the generator's draws moves them.
    np.testing.assert_allclose(R.bench_incoherent(LO, HI, 100, 1)[:2], [
        [1.1296638, 1.9970106, 1.1020653, -0.41483623, -0.7715843, -0.48225373, 0, np.inf],
        [-0.86930937, 1.4513144, 0.9690339, 0.74841744, -0.6118967, -0.25583932, 0, np.inf]],
        rtol=1e-6)
    g = two_triangles_and_a_sphere()
    rng = np.random.default_rng(1)
    np.testing.assert_allclose(R.incoherent(g, 3, rng)[:1], [
        [1.7595835, 3.4946296, 1.6993754, -2.4071424, -2.3788462, -1.0865506, 0, np.inf]],
        rtol=1e-6)
    np.testing.assert_allclose(R.grazing(g, 4, rng)[:1], [
        [0.53687447, 3.1453531, 7.2035508e-04, 0.092126846, -0.99574721, -3.1185953e-04, 0,
         np.inf]], rtol=1e-5)


def test_every_set_starts_at_t_zero_and_is_unbounded():
    for rays in crosscheck_sets(1)[:5] + [R.bench_incoherent(LO, HI, 50, 1),
                                          R.bench_all_miss(LO, HI, 50, 1),
                                          R.bench_camera(np.array([LO, HI]), 4, 3)]:
        assert rays.dtype == np.float32 and rays.shape[1] == 8
        assert np.all(rays[:, 6] == 0) and np.all(np.isposinf(rays[:, 7]))


def slab(rays, lo, hi):
    """Whether each ray meets the box [lo, hi] at some t >= 0 (float64 slab test)."""
    o, d = rays[:, 0:3].astype(np.float64), rays[:, 3:6].astype(np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        t1, t2 = (lo - o) / d, (hi - o) / d
    near = np.nanmax(np.minimum(t1, t2), axis=1)
    far = np.nanmin(np.maximum(t1, t2), axis=1)
    return (far >= np.maximum(near, 0))


def test_bench_sets_geometry():
    inc = R.bench_incoherent(LO, HI, 1000, 1)
    # Origins on the sphere of twice the bounding radius (sqrt(3) / 2) around the centre.
    radius = np.linalg.norm(inc[:, 0:3] - 0.5, axis=1)
    np.testing.assert_allclose(radius, np.sqrt(3), rtol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(inc[:, 3:6], axis=1), 1, rtol=1e-6)
    assert slab(inc, LO, HI).all()  # each is aimed at a point of the box
    miss = R.bench_all_miss(LO, HI, 1000, 1)
    np.testing.assert_array_equal(miss[:, 0:3], inc[:, 0:3])  # the same origins
    assert not slab(miss, LO, HI).any()  # all leave the box behind


def test_bench_camera_frames_every_point():
    pts = np.random.default_rng(0).random((200, 3))
    w, h = 16, 9
    rays = R.bench_camera(pts, w, h)
    assert len(rays) == w * h
    eye = rays[0, 0:3].astype(np.float64)
    assert np.all(rays[:, 0:3] == rays[0, 0:3])
    # The documented view: from azimuth 45, elevation 30 degrees (+x +y +z side), y up.
    az, el = np.radians(45), np.radians(30)
    forward = -np.array([np.sin(az) * np.cos(el), np.sin(el), np.cos(az) * np.cos(el)])
    d = rays[:, 3:6].astype(np.float64).reshape(h, w, 3)
    centre = d[h // 2, (w - 1) // 2: w // 2 + 1].mean(axis=0)  # row 4, columns 7 and 8
    np.testing.assert_allclose(centre / np.linalg.norm(centre), forward, atol=1e-6)
    rel = pts - eye
    depth = rel @ forward
    assert np.all(depth > 0)
    # Every point within the 40 degree vertical field of view (and the 16:9 horizontal one).
    up = np.cross(np.cross(forward, [0, 1, 0]), forward)
    up /= np.linalg.norm(up)
    right = np.cross(forward, up)
    tan_v = np.tan(np.radians(20))
    assert np.max(np.abs(rel @ up) / depth) <= tan_v
    assert np.max(np.abs(rel @ right) / depth) <= tan_v * w / h
    # ... tightly: the nearest distance that frames them, plus 2%.
    fill = max(np.max(np.abs(rel @ up) / depth) / tan_v,
               np.max(np.abs(rel @ right) / depth) / (tan_v * w / h))
    assert 0.9 < fill <= 1


def test_edge_rays_hit_their_targets():
    g = two_triangles_and_a_sphere()
    rays, t_target, must_hit = R.edges_and_vertices(g, 40, np.random.default_rng(5))
    assert len(rays) == 40 and np.all(t_target > 0)
    targets = rays[:, 0:3].astype(np.float64) + t_target[:, None] * rays[:, 3:6]
    # Every target lies in the square's plane, on its boundary or its diagonal.
    np.testing.assert_allclose(targets[:, 2], 0, atol=1e-6)
    x, y = targets[:, 0], targets[:, 1]
    on_diagonal = np.abs(x + y - 1) < 1e-6
    on_border = (np.minimum.reduce([x, y, 1 - x, 1 - y]) < 1e-6)
    assert np.all(on_diagonal | on_border)
    # The only shared edge is the diagonal: rays aimed at it (half the set) must hit.
    assert must_hit[:20].all() and on_diagonal[:20].all()
    with pytest.raises(AssertionError):  # and the check above can fail
        np.testing.assert_allclose(targets[:, 0], 0.5, atol=1e-6)
