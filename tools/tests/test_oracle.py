"""The independent oracle (lumis_tools.oracle: Embree picks the triangle, float64 gives t; the
float64 sphere test) against answers worked out by hand."""

from __future__ import annotations

import numpy as np
import pytest

from lumis_tools.geometry import Geometry
from lumis_tools.oracle import Oracle, plane_hit, sphere_roots, triangle_normals
from lumis_tools.rays import pack

# One triangle in the z = 0 plane, counter-clockwise seen from +z (normal +z).
TRIANGLE = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]


def geometry(triangles=(), spheres=()):
    g = Geometry()
    if len(triangles):
        g.add_triangles(np.array(triangles, np.float64))
    for s in spheres:
        g.add_sphere(s[:3], s[3])
    return g


def rays(*pairs):
    """float32 rays from (origin, direction) pairs."""
    return pack(np.array([o for o, _ in pairs], np.float64),
                np.array([d for _, d in pairs], np.float64))


def test_sphere_roots_by_hand():
    # From (0, 0, -5) along +z through a unit sphere at the origin: in at t = 4, out at 6.
    t0, t1 = sphere_roots(np.array([0.0, 0, -5]), np.array([0.0, 0, 1]), np.zeros(3), 1.0)
    assert (t0, t1) == (4.0, 6.0)
    # Unnormalised direction: t scales by 1 / |d|.
    t0, t1 = sphere_roots(np.array([0.0, 0, -5]), np.array([0.0, 0, 2]), np.zeros(3), 1.0)
    assert (t0, t1) == (2.0, 3.0)
    # Offset by 0.6 from the axis: chord half-length 0.8, so t = 5 -/+ 0.8.
    t0, t1 = sphere_roots(np.array([0.6, 0, -5]), np.array([0.0, 0, 1]), np.zeros(3), 1.0)
    assert t0 == pytest.approx(4.2, abs=1e-15) and t1 == pytest.approx(5.8, abs=1e-15)
    # Passing 1.5 from the centre: no real root.
    t0, t1 = sphere_roots(np.array([1.5, 0, -5]), np.array([0.0, 0, 1]), np.zeros(3), 1.0)
    assert np.isnan(t0) and np.isnan(t1)


def test_oracle_sphere_hit_inside_and_miss():
    g = geometry(spheres=[(0.0, 0.0, 0.0, 1.0)])
    h = Oracle(g).trace(rays(((0, 0, -5), (0, 0, 1)),    # head on: t 4, normal -z
                             ((0, 0, 0), (1, 0, 0)),     # from the centre: the far root, 1
                             ((0, 1.5, -5), (0, 0, 1)),  # passes above: miss
                             ((0, 0, 5), (0, 0, 1))))    # sphere behind the ray: miss
    assert h.t.tolist() == [4.0, 1.0, np.inf, np.inf]
    assert h.kind.tolist() == [0, 0, -1, -1]
    assert h.index.tolist() == [0, 0, -1, -1]
    np.testing.assert_array_equal(h.normal[:2], [[0, 0, -1], [1, 0, 0]])


def test_oracle_triangle_hit_barycentrics_and_miss():
    g = geometry(triangles=[TRIANGLE])
    h = Oracle(g).trace(rays(((0.5, 0.25, 3), (0, 0, -1)),   # straight down onto the plane
                             ((0.5, 0.5, -2), (0, 0, 1)),    # from below: same hit, t 2
                             ((1.5, 1.5, 3), (0, 0, -1))))   # beyond the hypotenuse: miss
    assert h.kind.tolist() == [1, 1, -1]
    assert h.t[:2].tolist() == [3.0, 2.0]
    # u, v are the weights of v1 = (2, 0, 0) and v2 = (0, 2, 0): x / 2 and y / 2.
    assert h.u[:2].tolist() == [0.25, 0.25]
    assert h.v[:2].tolist() == [0.125, 0.25]
    # The winding normal, whichever side the ray comes from (never flipped to the viewer).
    np.testing.assert_array_equal(h.normal[:2], [[0, 0, 1], [0, 0, 1]])
    assert np.isinf(h.t[2])


def test_oracle_picks_the_nearer_of_sphere_and_triangle():
    g = geometry(triangles=[TRIANGLE], spheres=[(0.5, 0.5, 2.0, 0.5)])
    h = Oracle(g).trace(rays(((0.5, 0.5, 5), (0, 0, -1)),    # sphere first, at t 2.5
                             ((0.5, 0.5, -1), (0, 0, 1))))   # triangle first, at t 1
    assert h.kind.tolist() == [0, 1]
    assert h.t.tolist() == [2.5, 1.0]


def test_oracle_float64_t_at_grazing_incidence():
    # 1e-4 rad above the plane from 1000 units away: the exact distance to z = 0.
    angle = 1e-4
    d = np.array([np.cos(angle), 0.0, -np.sin(angle)])
    o = np.array([0.5, 0.5, 0.0]) - 1000.0 * d
    r = pack(o[None], d[None])
    o32, d32 = r[0, 0:3].astype(np.float64), r[0, 3:6].astype(np.float64)
    big = [[-1e4, -1e4, 0.0], [1e4, -1e4, 0.0], [0.0, 1e4, 0.0]]
    h = Oracle(geometry(triangles=[big])).trace(r)
    assert h.kind[0] == 1
    assert h.t[0] == pytest.approx(-o32[2] / d32[2], rel=1e-13)


def test_plane_hit_and_normals_in_float64():
    tris = np.array([TRIANGLE])
    t, u, v = plane_hit(np.array([[1.0, 0.5, 4.0]]), np.array([[0.0, 0.0, -2.0]]), tris)
    assert (t[0], u[0], v[0]) == (2.0, 0.5, 0.25)
    np.testing.assert_array_equal(triangle_normals(tris), [[0, 0, 1]])
    # A degenerate triangle gets a zero normal, not NaN.
    np.testing.assert_array_equal(triangle_normals(np.zeros((1, 3, 3))), [[0, 0, 0]])


def test_oracle_refuses_rays_with_t_min():
    r = rays(((0, 0, -5), (0, 0, 1)))
    r[:, 6] = 0.5
    with pytest.raises(ValueError, match="t_min"):
        Oracle(geometry(spheres=[(0.0, 0.0, 0.0, 1.0)])).trace(r)
