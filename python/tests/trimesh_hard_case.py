"""A hard case for ray-mesh engines and its exact oracle (shared by test_trimesh_engine.py and
tools/bench_trimesh.py).

The solid: the box [0, 8]^3 minus the open box-shaped cavity (2, 5) x (2, 6) x (3, 6). Every
face of both boxes is split into unit squares of two triangles each, the diagonals alternating
like a chessboard, so vertices have 4, 5 or 6 triangles around them and rays meet every kind of
edge (square sides, diagonals, convex box edges, the cavity's reflex ones) and vertex (flat,
box corners, cavity corners). Rays run between points of the half-unit lattice and through
vertices and edge points of the surface; points for containment lie on the same lattice.

The oracle uses only the solid's definition (the twelve rectangles bounding it), never the
triangles, and exact rational arithmetic (`fractions.Fraction`): a ray meets the surface in a
finite set of points (rays that run along a piece of surface are set aside, as their count
depends on a tie-breaking rule), each of which is one hit; it is a crossing when the points
just before and just after it lie on different sides of the solid, else a touch. A point is
inside when it lies in the closed solid (the surface counts as inside).
"""

from __future__ import annotations

from fractions import Fraction
from typing import List, Optional, Tuple

import numpy as np

OUTER = ((0, 8), (0, 8), (0, 8))
CAVITY = ((2, 5), (2, 6), (3, 6))


def _box_faces(box, outward: bool, vertex_id, faces: List[Tuple[int, int, int]]) -> None:
    """Unit-square triangles of the six faces of `box`, normals pointing out of the box when
    `outward`, into it otherwise."""
    for axis in range(3):
        u_axis, v_axis = (axis + 1) % 3, (axis + 2) % 3
        for side in (0, 1):
            c = box[axis][side]
            # (u, v, axis) is right-handed, so counter-clockwise in (u, v) faces +axis.
            flip = (side == 0) == outward
            for u in range(box[u_axis][0], box[u_axis][1]):
                for v in range(box[v_axis][0], box[v_axis][1]):
                    corner = []
                    for du, dv in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = [0, 0, 0]
                        p[axis], p[u_axis], p[v_axis] = c, u + du, v + dv
                        corner.append(vertex_id(tuple(p)))
                    a, b, cc, d = corner
                    if (u + v + c) % 2:
                        tris = [(a, b, cc), (a, cc, d)]
                    else:
                        tris = [(a, b, d), (b, cc, d)]
                    for t in tris:
                        faces.append((t[0], t[2], t[1]) if flip else t)


def mesh_arrays() -> Tuple[np.ndarray, np.ndarray]:
    """`(vertices float64 (V, 3), faces int64 (F, 3))` of the solid, welded, outward normals."""
    ids: dict = {}

    def vertex_id(p):
        return ids.setdefault(p, len(ids))

    faces: List[Tuple[int, int, int]] = []
    _box_faces(OUTER, True, vertex_id, faces)
    _box_faces(CAVITY, False, vertex_id, faces)
    vertices = np.array(sorted(ids, key=ids.get), dtype=np.float64)
    return vertices, np.array(faces, dtype=np.int64)


def _rectangles():
    """The twelve closed rectangles bounding the solid: (axis, coordinate, box)."""
    return [(axis, box[axis][side], box) for box in (OUTER, CAVITY)
            for axis in range(3) for side in (0, 1)]


def inside(p) -> bool:
    """Whether point `p` (exact numbers) lies in the closed solid."""
    in_outer = all(OUTER[k][0] <= p[k] <= OUTER[k][1] for k in range(3))
    in_cavity = all(CAVITY[k][0] < p[k] < CAVITY[k][1] for k in range(3))
    return in_outer and not in_cavity


def _inside_near(p, d, sign: int) -> bool:
    """Whether the points `p + s d` for small `s` of the given sign are in the solid (the ray
    is assumed not to run along the surface there): each bound compared lexicographically on
    (coordinate, its derivative)."""

    def ge(k, b):  # p[k] + s d[k] >= b, for all small s of this sign
        return p[k] > b or (p[k] == b and sign * d[k] >= 0)

    def le(k, b):
        return p[k] < b or (p[k] == b and sign * d[k] <= 0)

    def gt(k, b):
        return p[k] > b or (p[k] == b and sign * d[k] > 0)

    def lt(k, b):
        return p[k] < b or (p[k] == b and sign * d[k] < 0)

    in_outer = all(ge(k, OUTER[k][0]) and le(k, OUTER[k][1]) for k in range(3))
    in_cavity = all(gt(k, CAVITY[k][0]) and lt(k, CAVITY[k][1]) for k in range(3))
    return in_outer and not in_cavity


def ray_hits(origin, direction) -> Optional[List[Tuple[Fraction, bool]]]:
    """The exact hits of the ray `origin + t direction`, `t >= 0`, as sorted `(t, crossing)`,
    or None when the ray runs along a piece of the surface."""
    o = [Fraction(x) for x in origin]
    d = [Fraction(x) for x in direction]
    ts = set()
    for axis, c, box in _rectangles():
        others = [k for k in range(3) if k != axis]
        if d[axis] == 0:
            if o[axis] != c:
                continue
            # In the rectangle's plane: does the ray (t >= 0) overlap the rectangle?
            lo, hi = Fraction(0), None
            empty = False
            for k in others:
                a, b = box[k]
                if d[k] == 0:
                    empty |= not (a <= o[k] <= b)
                    continue
                t1, t2 = sorted(((a - o[k]) / d[k], (b - o[k]) / d[k]))
                lo, hi = max(lo, t1), t2 if hi is None else min(hi, t2)
            if not empty and (hi is None or lo < hi):
                return None  # along a piece of surface
            if not empty and hi is not None and lo == hi:
                ts.add(lo)  # meets the rectangle at one point of its border
            continue
        t = (c - o[axis]) / d[axis]
        if t < 0:
            continue
        p = [o[k] + t * d[k] for k in range(3)]
        if all(box[k][0] <= p[k] <= box[k][1] for k in others):
            ts.add(t)
    hits = []
    for t in sorted(ts):
        p = [o[k] + t * d[k] for k in range(3)]
        before = _inside_near(p, d, -1) if t > 0 else None
        after = _inside_near(p, d, +1)
        hits.append((t, before is not None and before != after))
    return hits


def lattice_rays(count: int, seed: int = 0) -> Tuple[np.ndarray, np.ndarray]:
    """`count` rays `(origins, directions)`, float64, from half-unit lattice points off the
    surface (two in three near the solid, one in three 40-80 units away) through a vertex or
    an edge point of the surface (a half-unit lattice point on it: vertices, the midpoints of
    unit edges and of the squares' diagonals)."""
    rng = np.random.default_rng(seed)
    rects = _rectangles()
    origins, directions = [], []
    while len(origins) < count:
        if len(origins) % 3 == 2:
            o = rng.integers(80, 161, size=3) / 2.0 * rng.choice([-1, 1], size=3) + 4
        else:
            o = rng.integers(-8, 25, size=3) / 2.0
        if _on_surface(o):
            continue
        axis, c, box = rects[rng.integers(len(rects))]
        target = np.empty(3)
        for k in range(3):
            a, b = box[k]
            target[k] = c if k == axis else rng.integers(2 * a, 2 * b + 1) / 2.0
        origins.append(o)
        directions.append(target - o)
    return np.array(origins), np.array(directions)


def lattice_points(count: int, seed: int = 0) -> np.ndarray:
    """`count` points of the half-unit lattice in [-1, 9]^3, float64."""
    rng = np.random.default_rng(seed)
    return rng.integers(-2, 19, size=(count, 3)) / 2.0


def _on_surface(p) -> bool:
    for axis, c, box in _rectangles():
        if p[axis] == c and all(box[k][0] <= p[k] <= box[k][1] for k in range(3) if k != axis):
            return True
    return False


def crossing_counts(origins, directions):
    """Per ray: the exact number of hits (crossings and touches), or -1 for a ray along the
    surface; and the exact hits themselves."""
    counts = np.empty(len(origins), dtype=np.int64)
    exact = []
    for i, (o, d) in enumerate(zip(origins, directions)):
        h = ray_hits(o.tolist(), d.tolist())
        exact.append(h)
        counts[i] = -1 if h is None else len(h)
    return counts, exact


def containment(points) -> np.ndarray:
    return np.array([inside([Fraction(x) for x in p.tolist()]) for p in points])
