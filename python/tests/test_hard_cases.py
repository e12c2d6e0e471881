"""The hard cases through the package, each with a known exact answer: rays from far away (the
octahedron |x| + |y| + |z| <= 1 seen from 1e6 to 1e37 along an axis hits its vertex at exactly
|o| - 1 as f32 rounds it), rays through the shared edges and vertices of a closed cube (one
crossing in, one out: the all-hits rule), rays grazing its silhouette edges (flagged grazes),
and the same rows as `lumis hits`."""

from __future__ import annotations

import numpy as np
import pytest

import lumis
from conftest import bits, cli_hits

OCTAHEDRON = """v 1 0 0
v -1 0 0
v 0 1 0
v 0 -1 0
v 0 0 1
v 0 0 -1
f 1 3 5
f 3 2 5
f 2 4 5
f 4 1 5
f 3 1 6
f 2 3 6
f 4 2 6
f 1 4 6
"""

# The cube [-1, 1]^3, each face split along a diagonal: every ray below meets it exactly on an
# edge or a vertex shared by several triangles.
CUBE = """v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
f 1 3 2
f 1 4 3
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 2 3 7
f 2 7 6
f 3 4 8
f 3 8 7
f 4 1 5
f 4 5 8
"""


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_far_origins_hit_the_vertex_exactly(tmp_path, cli):
    path = write(tmp_path, "octahedron.obj", OCTAHEDRON)
    s = lumis.load(path)
    dists = np.array([1e6, 1e9, 1e12, 1e18, 1e24, 1e30, 1e37], np.float32)
    rays = np.zeros((len(dists) * 3, 8), np.float32)
    for axis in range(3):
        rows = rays[axis::3]
        rows[:, axis] = dists
        rows[:, 3 + axis] = -1.0
        rows[:, 7] = np.inf
    h = s.intersect(rays[:, 0:3], rays[:, 3:6], rays[:, 6], rays[:, 7])
    # The vertex at distance 1 from the centre: t = |o| - 1, rounded once to f32 (which is |o|
    # itself beyond 2^24).
    expected = np.repeat(dists.astype(np.float64) - 1.0, 3).astype(np.float32)
    assert h.t.tolist() == expected.tolist()
    assert (h.prim_id >= 0).all()
    assert bits(h.rows()).tolist() == bits(cli_hits(cli, tmp_path, path, rays)).tolist()
    # Aimed a milliradian off the octahedron from 1e30: every ray misses.
    off = rays.copy()
    off[:, 3:6] += np.float32(1e-3) * np.roll(off[:, 3:6], 1, axis=1)
    far = off[np.abs(off[:, 0:3]).max(axis=1) >= 1e18]
    assert not s.occluded(far[:, 0:3], far[:, 3:6], far[:, 6], far[:, 7]).any()


def cube_rays():
    """Rays through shared edges and vertices of the cube, along and across the axes."""
    o, d = [], []
    # Along z: through the top and bottom faces' edges (in a side face's plane), through their
    # split diagonals (0, 0) and (0.5, 0.5).
    for x, y in [(0.0, 1.0), (1.0, 0.0), (0.0, -1.0), (-1.0, 0.0), (0.0, 0.0), (0.5, 0.5)]:
        o.append((x, y, 5.0))
        d.append((0.0, 0.0, -1.0))
    # Through two opposite vertices (the main diagonal) and through edge midpoints.
    o += [(5.0, 5.0, 5.0), (5.0, 0.0, 5.0), (0.0, 5.0, 5.0)]
    d += [(-1.0, -1.0, -1.0), (-1.0, 0.0, -1.0), (0.0, -1.0, -1.0)]
    return np.array(o, np.float32), np.array(d, np.float32)


def test_all_hits_count_each_crossing_once_through_edges_and_vertices(tmp_path):
    s = lumis.load(write(tmp_path, "cube.obj", CUBE))
    o, d = cube_rays()
    a = s.intersect_all(o, d)
    for i in range(len(o)):
        mine = a.ray == i
        # (x, y) = (+-1, 0) etc. run along a side face's plane: those are grazes on the
        # silhouette, not crossings; the rest cross the surface once in, once out.
        t, graze = a.t[mine], a.graze[mine]
        along_face = abs(o[i][0]) == 1.0 or abs(o[i][1]) == 1.0
        if along_face:
            assert not (~graze).sum() % 2, (i, t, graze)
        else:
            assert (~graze).sum() == 2, (i, t, graze)
            # Entry and exit of the unit-half-width cube along the ray, exactly.
            length = float(np.linalg.norm(d[i].astype(np.float64)))
            centre = float(np.dot(-o[i].astype(np.float64), d[i]) / length ** 2)
            assert t[0] < centre < t[-1]
    # The closest hit is the first crossing or graze, bit for bit.
    h = s.intersect(o, d)
    firsts = [a.t[a.ray == i][0] for i in range(len(o))]
    assert bits(h.t).tolist() == bits(np.array(firsts, np.float32)).tolist()


def test_inside_outside_parity_on_the_cube(tmp_path):
    """Between consecutive crossings the ray alternates outside, inside (exact: the cube)."""
    s = lumis.load(write(tmp_path, "cube.obj", CUBE))
    rng = np.random.default_rng(7)
    # Integer points on the cube's edges and faces and random ones, from outside.
    targets = rng.integers(-1, 2, size=(300, 3)).astype(np.float32)
    targets[150:] = rng.uniform(-1.2, 1.2, size=(150, 3)).astype(np.float32)
    o = rng.normal(size=(300, 3)).astype(np.float32) * 4
    o += np.sign(o) * 2
    d = targets - o
    keep = np.linalg.norm(d, axis=1) > 0
    o, d = o[keep], d[keep]
    a = s.intersect_all(o, d)
    for i in range(len(o)):
        crossings = a.t[(a.ray == i) & ~a.graze].astype(np.float64)
        # Sample between crossings, well away from them.
        end = crossings[-1] + 10.0 if len(crossings) else 10.0
        edges = np.concatenate([[0.0], crossings, [end]])
        for k in range(len(edges) - 1):
            lo, hi = edges[k], edges[k + 1]
            if hi - lo < 1e-3:
                continue
            p = o[i].astype(np.float64) + 0.5 * (lo + hi) * d[i].astype(np.float64)
            inside = bool(np.all(np.abs(p) < 1.0))
            boundary = np.any(np.abs(np.abs(p) - 1.0) < 1e-9)
            if not boundary:
                assert inside == (k % 2 == 1), (i, k, crossings)
