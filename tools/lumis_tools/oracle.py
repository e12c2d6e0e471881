"""The independent answer to a ray query: Embree (robust mode) for triangles, a float64
analytic test for spheres, the nearer of the two."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .embree import EmbreeScene
from .geometry import Geometry

# Ray x sphere pairs per numpy batch: bounds memory at a few hundred MiB.
_PAIRS_PER_BATCH = 2_000_000


@dataclass
class OracleHits:
    """Per ray: t (inf = miss), kind (-1 miss, 0 sphere, 1 triangle), index into the
    geometry's spheres or triangles, barycentric u, v (weights of v1, v2; 0 for spheres), and
    the unit geometric normal (triangles by winding, spheres outward)."""

    t: np.ndarray
    kind: np.ndarray
    index: np.ndarray
    u: np.ndarray
    v: np.ndarray
    normal: np.ndarray
    # Embree's own float32 t for triangle hits (t above is recomputed in float64), inf elsewhere.
    t_embree: np.ndarray | None = None


class Oracle:
    """Traces rays against a Geometry without any lumis code."""

    def __init__(self, geometry: Geometry):
        self.geometry = geometry
        self._embree = None
        if len(geometry.triangles):
            self._embree = EmbreeScene(geometry.triangles, robust=True)

    def trace(self, rays: np.ndarray) -> OracleHits:
        """Closest hits of `(N, 8)` float32 rays with t in [0, t_max]. Embree through embreex
        has no t_min, so every ray must have t_min = 0."""
        rays = np.ascontiguousarray(rays, np.float32)
        if np.any(rays[:, 6] != 0):
            raise ValueError("the oracle needs t_min = 0 on every ray (embreex has no tnear)")
        n = len(rays)
        t = np.full(n, np.inf)
        kind = np.full(n, -1, np.int64)
        index = np.full(n, -1, np.int64)
        u = np.zeros(n)
        v = np.zeros(n)
        normal = np.zeros((n, 3))
        t_embree = np.full(n, np.inf)
        t_max = rays[:, 7].astype(np.float64)
        if self._embree is not None and n:
            out = self._embree.intersect(rays)
            hit = out["primID"] >= 0
            t_embree[hit] = out["tfar"][hit]
            kind[hit] = 1
            index[hit] = out["primID"][hit]
            # Embree decides which triangle; where on it (t, u, v) is recomputed in float64 from
            # the same float32 data, so grazing rays (where a float32 plane test loses most of
            # its digits) still get a trustworthy reference t.
            tris = self.geometry.triangles[index[hit]]
            t[hit], u[hit], v[hit] = plane_hit(rays[hit, 0:3].astype(np.float64),
                                               rays[hit, 3:6].astype(np.float64), tris)
            normal[hit] = triangle_normals(tris)
        if len(self.geometry.spheres) and n:
            st, si = nearest_spheres(rays, self.geometry.spheres)
            closer = (st < t) & (st <= t_max)
            t[closer] = st[closer]
            kind[closer] = 0
            index[closer] = si[closer]
            u[closer] = v[closer] = 0
            o = rays[closer, 0:3].astype(np.float64)
            d = rays[closer, 3:6].astype(np.float64)
            c = self.geometry.spheres[si[closer], :3]
            p = o + st[closer, None] * d
            nrm = p - c
            normal[closer] = nrm / np.linalg.norm(nrm, axis=1, keepdims=True)
        return OracleHits(t, kind, index, u, v, normal, t_embree)


def plane_hit(o, d, tris):
    """Ray parameter and barycentrics (weights of v1, v2) of rays meeting the planes of
    `(M, 3, 3)` triangles, in float64."""
    e1 = tris[:, 1] - tris[:, 0]
    e2 = tris[:, 2] - tris[:, 0]
    n = np.cross(e1, e2)
    den = np.einsum("ij,ij->i", n, d)
    w = tris[:, 0] - o
    t = np.einsum("ij,ij->i", n, w) / den
    p = o + t[:, None] * d - tris[:, 0]
    nn = np.einsum("ij,ij->i", n, n)
    u = np.einsum("ij,ij->i", np.cross(p, e2), n) / nn
    v = np.einsum("ij,ij->i", np.cross(e1, p), n) / nn
    return t, u, v


def triangle_normals(tris):
    """Unit normals cross(v1 - v0, v2 - v0) of `(M, 3, 3)` triangles (0 for degenerate)."""
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return n / np.where(length > 0, length, 1)


def sphere_roots(o, d, c, r):
    """Both ray parameters (t0 <= t1, NaN when missed) of rays o + t d against spheres (c, r),
    broadcasting, in float64 with the cancellation-free forms: the discriminant from the
    perpendicular distance (r - l)(r + l), and the smaller root from c / q."""
    f = o - c
    a = np.einsum("...k,...k->...", d, d)
    b = np.einsum("...k,...k->...", f, d)  # half of the usual b
    perp = f - (b / a)[..., None] * d
    ell = np.sqrt(np.einsum("...k,...k->...", perp, perp))
    disc = (r - ell) * (r + ell)  # = (b^2 - a c) / a
    fl = np.sqrt(np.einsum("...k,...k->...", f, f))
    cc = (fl - r) * (fl + r)
    with np.errstate(invalid="ignore", divide="ignore"):
        q = -b - np.copysign(np.sqrt(a * disc), b)
        r0 = cc / q
        r1 = q / a
    t0 = np.where(disc >= 0, np.minimum(r0, r1), np.nan)
    t1 = np.where(disc >= 0, np.maximum(r0, r1), np.nan)
    return t0, t1


def nearest_spheres(rays, spheres):
    """Nearest sphere hit with t > 0 per ray, brute force in float64: (t or inf, index or -1)."""
    n, s = len(rays), len(spheres)
    best_t = np.full(n, np.inf)
    best_i = np.full(n, -1, np.int64)
    o_all = rays[:, 0:3].astype(np.float64)
    d_all = rays[:, 3:6].astype(np.float64)
    step = max(1, _PAIRS_PER_BATCH // max(s, 1))
    c = spheres[None, :, :3]
    r = spheres[None, :, 3]
    for start in range(0, n, step):
        o = o_all[start:start + step, None, :]
        d = d_all[start:start + step, None, :]
        t0, t1 = sphere_roots(o, d, c, r)
        t = np.where(t0 > 0, t0, np.where(t1 > 0, t1, np.inf))
        t = np.where(np.isnan(t), np.inf, t)
        i = np.argmin(t, axis=1)
        tt = t[np.arange(len(t)), i]
        best_t[start:start + step] = tt
        best_i[start:start + step] = np.where(np.isfinite(tt), i, -1)
    return best_t, best_i
