"""The classes crosscheck_exr gives pixels where lumis and the oracle hit different primitives
(lumis_tools.exr_classify): the legitimate ones at shared edges, silhouettes and sphere rims,
and mismatch / unmapped where neither answer can be explained."""

from __future__ import annotations

import numpy as np

from lumis_tools.exr_classify import classify
from lumis_tools.prims import Prims

# Two triangles of the unit square in z = 0, sharing the diagonal from (1, 0) to (0, 1).
A = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
B = [[1, 0, 0], [1, 1, 0], [0, 1, 0]]
SPHERE = [0.0, 0.0, 5.0, 1.0]
NONE = [[0, 0, 0]] * 3
REL = 2.0 ** -16


def prims(*items):
    """Per ray: a triangle (3 corners), a sphere (4 numbers) or None (a miss)."""
    kind = np.array([-1 if p is None else (0 if len(p) == 4 else 1) for p in items])
    tris = np.array([p if p is not None and len(p) == 3 else NONE for p in items], np.float64)
    spheres = np.array([p if p is not None and len(p) == 4 else [0] * 4 for p in items],
                       np.float64)
    return Prims(kind, tris, spheres)


def down_at(x, y, z=1.0):
    return [x, y, z], [0.0, 0.0, -1.0]


def run(rays, lum, orc, mapped=None):
    o = np.array([r[0] for r in rays], np.float64)
    d = np.array([r[1] for r in rays], np.float64)
    n = len(rays)
    mapped = np.ones(n, bool) if mapped is None else np.asarray(mapped)
    classes, _, _ = classify(o, d, lum, mapped, np.zeros(n, bool), orc, np.zeros(n, bool), REL)
    return list(classes)


def test_shared_edge_tie_and_true_mismatch():
    rays = [down_at(0.5, 0.5),      # on the diagonal: either triangle is right
            down_at(0.25, 0.25),    # inside A; lumis says B, which the ray does not reach
            down_at(0.25, 0.25)]    # inside A; the oracle says B: same plane, same depth
    assert run(rays, prims(A, B, A), prims(B, A, B)) == ["shared_edge", "mismatch", "tie"]


def test_silhouette_and_grazing_against_a_miss():
    rays = [down_at(1.0, 0.5),                 # on the square's outer edge x = 1
            ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),  # touching the sphere's rim at x = r
            down_at(0.3, 0.3)]                 # inside A, missed by the oracle: wrong
    lum = prims(B, SPHERE, A)
    assert run(rays, lum, prims(None, None, None)) == ["silhouette", "grazing", "mismatch"]


def test_unmapped_and_unreached_primitives():
    # From z = 10 down through A at (0.25, 0.25); the oracle sees a sphere in front of it.
    ray = down_at(0.25, 0.25, 10.0)
    ball = [0.25, 0.25, 5.0, 1.0]
    assert run([ray], prims(A), prims(ball)) == ["mismatch"]
    # ... and when lumis's triangle has no counterpart in the independent loader: unmapped.
    assert run([ray], prims(A), prims(ball), mapped=[False]) == ["unmapped"]
    # lumis names a triangle the ray does not reach at all.
    assert run([down_at(0.9, 0.9)], prims(A), prims(B)) == ["mismatch"]
