"""lumis's own primitives (`lumis hits --triangles-out --spheres-out`) looked up by primitive
id, for judging each engine's hit on the primitive that engine reported."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .geometry import Geometry


@dataclass
class Prims:
    """Primitives to probe, one per ray: kind (-1 none, 0 sphere, 1 triangle), triangle
    corners (k, 3, 3) and sphere rows (k, 4), whichever the kind says."""

    kind: np.ndarray
    tris: np.ndarray
    spheres: np.ndarray

    @staticmethod
    def of_oracle(geom, kind, index):
        k = len(kind)
        tris, spheres = np.zeros((k, 3, 3)), np.zeros((k, 4))
        tri, sph = kind == 1, kind == 0
        tris[tri] = geom.triangles[index[tri]]
        spheres[sph] = geom.spheres[index[sph]]
        return Prims(kind, tris, spheres)


class LumisPrims:
    """lumis's own primitives (`lumis hits --triangles-out/--spheres-out`) by primitive id."""

    def __init__(self, l_tris, l_spheres):
        n = max(int(max([-1, *l_tris[:, 0], *l_spheres[:, 0]])) + 1, 1)
        self.kind = np.full(n, -1, np.int64)
        self.tris = np.zeros((n, 3, 3))
        self.spheres = np.zeros((n, 4))
        ti = l_tris[:, 0].astype(np.int64)
        si = l_spheres[:, 0].astype(np.int64)
        self.kind[ti], self.kind[si] = 1, 0
        self.tris[ti] = l_tris[:, 1:].astype(np.float64).reshape(-1, 3, 3)
        self.spheres[si] = l_spheres[:, 1:].astype(np.float64)

    @cached_property
    def geometry(self):
        """The tables as a Geometry indexed by primitive id (rows of the other kind are 0)."""
        return Geometry(triangles=self.tris, spheres=self.spheres)

    def kind_index(self, prim):
        """(kind, index into `geometry`) per primitive id; -1 for -1 or unknown ids."""
        ok = (prim >= 0) & (prim < len(self.kind))
        kind = np.where(ok, self.kind[np.where(ok, prim, 0)], -1)
        return kind, np.where(kind >= 0, prim, -1)

    def of(self, prim):
        ok = (prim >= 0) & (prim < len(self.kind))
        p = np.where(ok, prim, 0)
        return Prims(np.where(ok, self.kind[p], -1), self.tris[p], self.spheres[p])
