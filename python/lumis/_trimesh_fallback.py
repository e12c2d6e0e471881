"""Stand-ins for `Scene.from_arrays` and `Scene.contains` while a build lacks them (issue 39,
items 1 and 2); `lumis.trimesh` uses them only then. Delete this module once both exist.

- A mesh from arrays goes through an OBJ file: float32 vertices written with 9 significant
  digits (which read back to the same float32), faces 1-based. The OBJ loader skips faces of
  exactly zero area, so the loaded primitives are matched back to face rows.
- Containment from `intersect_all`: a point from which some axis ray hits the surface at
  `t = 0` is on the surface (inside); otherwise the parity of the crossings along +x, which
  the all-hits rule counts exactly for closed meshes.
"""

from __future__ import annotations

import os
import tempfile
from typing import Optional, Tuple

import numpy as np

from . import Scene, load


def scene_from_arrays(
    vertices: np.ndarray, faces: np.ndarray
) -> Tuple[Scene, Optional[np.ndarray]]:
    """The scene and, when the loader skipped faces, the face row of each primitive."""
    v32 = np.asarray(vertices, dtype=np.float64).astype(np.float32)
    faces = np.asarray(faces, dtype=np.int64)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "mesh.obj")
        with open(path, "w") as f:
            np.savetxt(f, v32, fmt="v %.9g %.9g %.9g")
            np.savetxt(f, faces + 1, fmt="f %d %d %d")
        scene = load(path)
    tris = scene.triangles()
    loaded = tris[:, 1:].reshape(-1, 3, 3)
    wanted = v32[faces]
    if len(loaded) == len(faces) and np.array_equal(loaded, wanted):
        return scene, None
    return scene, _match_in_order(loaded, wanted, tris[:, 0].astype(np.int64))


def _match_in_order(loaded: np.ndarray, wanted: np.ndarray, prim: np.ndarray) -> np.ndarray:
    """Face row of each loaded primitive: the loader keeps faces in file order and skips
    some, so each primitive is the next face with the same corners (in any rotation)."""
    face_of_prim = np.full(int(prim.max()) + 1 if len(prim) else 0, -1, dtype=np.int64)
    row = 0
    for k, tri in enumerate(loaded):
        while row < len(wanted) and not _same_triangle(tri, wanted[row]):
            row += 1
        if row == len(wanted):
            raise RuntimeError("lumis.trimesh: loaded triangles do not match the mesh's faces")
        face_of_prim[prim[k]] = row
        row += 1
    return face_of_prim


def _same_triangle(a: np.ndarray, b: np.ndarray) -> bool:
    return any(np.array_equal(a, np.roll(b, r, axis=0)) for r in range(3))


def contains(scene: Scene, points: np.ndarray, t_min: float) -> np.ndarray:
    """Exact containment of float32 `points` in the scene's closed mesh, surface inside."""
    n = len(points)
    origins = np.tile(points, (3, 1))
    directions = np.repeat(np.eye(3), n, axis=0)
    hits = scene.intersect_all(origins, directions, t_min=t_min)
    on_surface = np.zeros(n, dtype=bool)
    on_surface[hits.ray[hits.t == 0] % n] = True
    along_x = (hits.ray < n) & ~hits.graze & (hits.t > 0)
    crossings = np.bincount(hits.ray[along_x], minlength=n)
    return on_surface | (crossings % 2 == 1)
