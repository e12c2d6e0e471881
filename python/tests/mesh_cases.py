"""Meshes and rays for the array tests: a closed box with integer coordinates whose faces are
split into unit squares (so rays can pass exactly through its edges and vertices), degenerate
faces mixed in, OBJ writing, and rays aimed at vertices, edge midpoints and random points."""

from __future__ import annotations

from pathlib import Path

import numpy as np


def split_box(n: int = 2):
    """The closed box [0, n]^3, each face split into n x n unit squares of two triangles,
    wound outwards, vertices shared: float64 `(V, 3)`, int64 `(F, 3)`."""
    index: dict = {}
    vertices: list = []

    def vertex(p) -> int:
        p = tuple(int(x) for x in p)
        if p not in index:
            index[p] = len(vertices)
            vertices.append(p)
        return index[p]

    faces = []
    for axis in range(3):
        u_axis, v_axis = (axis + 1) % 3, (axis + 2) % 3
        for side in (0, n):
            for i in range(n):
                for j in range(n):
                    def at(a, b):
                        p = [0, 0, 0]
                        p[axis], p[u_axis], p[v_axis] = side, a, b
                        return vertex(p)
                    quad = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]
                    # (u, v, axis) is right-handed: counter-clockwise in (u, v) faces +axis.
                    if side == 0:
                        quad = quad[::-1]
                    faces.append([quad[0], quad[1], quad[2]])
                    faces.append([quad[0], quad[2], quad[3]])
    return np.array(vertices, np.float64), np.array(faces, np.int64)


def degenerate_faces(vertices: np.ndarray) -> np.ndarray:
    """Zero-area faces on `vertices` of `split_box`: a repeated index, three equal indices,
    and three collinear vertices along an edge of the box."""
    def find(p):
        return int(np.flatnonzero((vertices == p).all(axis=1))[0])
    a, b, c = find((0, 0, 0)), find((1, 0, 0)), find((2, 0, 0))
    return np.array([[a, a, b], [c, c, c], [a, b, c], [b, c, a]], np.int64)


def mix_in(faces: np.ndarray, extra: np.ndarray, seed: int = 0):
    """`faces` with the rows of `extra` inserted at seeded random places, and the mask of the
    rows that came from `faces`."""
    rng = np.random.default_rng(seed)
    n = len(faces) + len(extra)
    at = np.sort(rng.choice(n, size=len(extra), replace=False))
    keep = np.ones(n, bool)
    keep[at] = False
    out = np.empty((n, 3), faces.dtype)
    out[keep] = faces
    out[~keep] = extra
    return out, keep


def zero_area(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Which faces have exactly zero area (exact: the vertices are small integers)."""
    p = vertices[faces].astype(np.int64)
    return (np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]) == 0).all(axis=1)


def write_obj(path: Path, vertices: np.ndarray, faces: np.ndarray) -> Path:
    """An OBJ of the float32 values of `vertices` (written so they read back exactly)."""
    v32 = np.asarray(vertices, np.float32)
    lines = ["v " + " ".join(repr(float(x)) for x in row) for row in v32]
    lines += ["f " + " ".join(str(int(i) + 1) for i in row) for row in faces]
    path.write_text("\n".join(lines) + "\n")
    return path


def aimed_rays(vertices: np.ndarray, faces: np.ndarray, n_random: int, seed: int):
    """float32 origins and directions: from seeded random points around the mesh towards
    every vertex, every edge midpoint and `n_random` random points of its bounding box."""
    rng = np.random.default_rng(seed)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    centre, size = (lo + hi) / 2, float((hi - lo).max())
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    midpoints = (vertices[edges[:, 0]] + vertices[edges[:, 1]]) / 2
    targets = np.concatenate([
        vertices,
        midpoints,
        rng.uniform(lo - 0.25 * size, hi + 0.25 * size, size=(n_random, 3)),
    ])
    # Origins on a sphere around the mesh, at lattice points (halves) so that many rays run
    # along the lattice's planes and lines too.
    o = rng.normal(size=(len(targets), 3))
    o = centre + 2.0 * size * o / np.linalg.norm(o, axis=1, keepdims=True)
    o = np.round(o * 2) / 2
    d = targets - o
    keep = np.linalg.norm(d, axis=1) > 0
    return o[keep].astype(np.float32), d[keep].astype(np.float32)
