"""The one wrapper around embreex that every tool uses: a scene of float32 triangles, its
commit, and closest-hit queries returning embreex's full hit record.

embreex has no tnear: every ray starts at t = 0 (the ray sets offset secondary-like origins
from the surface instead)."""

from __future__ import annotations

import time

import numpy as np


class EmbreeScene:
    """`(M, 3, 3)` triangles in one Embree triangle mesh, primitive i = triangle i. robust=True
    sets RTC_SCENE_FLAG_ROBUST (no accuracy-reducing optimisations, so rays do not slip through
    shared edges): the closest match to lumis's watertight test."""

    def __init__(self, triangles, robust=True):
        # Imported here: tools without triangles (or without Embree) never load TBB.
        from embreex import rtcore_scene as rtcs
        from embreex.mesh_construction import TriangleMesh

        self.robust = robust
        self.scene = rtcs.EmbreeScene(robust=robust)
        verts = np.ascontiguousarray(np.asarray(triangles).reshape(-1, 3), np.float32)
        faces = np.arange(len(verts), dtype=np.int32).reshape(-1, 3)
        # Kept alive as long as the scene, which refers to the mesh.
        self._mesh = TriangleMesh(self.scene, verts, faces)

    def commit(self):
        """Builds the BVH now; returns its (wall, cpu) seconds. embreex commits lazily on the
        first query, so this traces one ray and times that."""
        one = np.zeros((1, 3), np.float32)
        wall, cpu = time.perf_counter(), time.process_time()
        self.scene.run(one, np.ones((1, 3), np.float32))
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        assert self.scene.is_committed
        return wall, cpu

    def intersect(self, rays):
        """Closest hits of `(N, 8)` float32 rays (origin, direction, t_min = 0, t_max): the dict
        of embreex's `run(..., output=True)`: tfar (the hit t), primID and geomID (-1 on a
        miss), u, v, Ng."""
        return self.timed_intersect(rays)[1]

    def timed_intersect(self, rays):
        """(seconds, hits) of `intersect`; the seconds are embreex's query alone, not the
        copying of the rays into its arrays (the benchmark's figure)."""
        rays = np.asarray(rays, np.float32)
        origins = np.ascontiguousarray(rays[:, 0:3])
        dirs = np.ascontiguousarray(rays[:, 3:6])
        # A fresh array (embreex writes the hits' t into it); t_max = inf goes in as 3e38, as
        # the oracle has always passed it (a miss keeps that value as its tfar).
        dists = np.minimum(rays[:, 7], np.float32(3.0e38)).astype(np.float32)
        start = time.perf_counter()
        out = self.scene.run(origins, dirs, dists=dists, query="INTERSECT", output=True)
        return time.perf_counter() - start, out
