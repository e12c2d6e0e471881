"""Classifying the pixels where lumis and the oracle hit different primitives: geometry probes
of one ray against one primitive, in float64, and the classes of crosscheck_exr's doc
(shared_edge, edge, silhouette, grazing, tie, retriangulated are legitimate; mismatch and
unmapped fail)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .oracle import sphere_roots

CLASSES = ["match", "shared_edge", "edge", "silhouette", "grazing", "tie", "retriangulated",
           "mismatch", "unmapped"]
LEGIT = {"shared_edge", "edge", "silhouette", "grazing", "tie", "retriangulated"}
SAME_DEPTH = {"shared_edge", "edge", "tie", "retriangulated"}


def _seg_dist(p, a, b):
    ab = b - a
    den = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300)
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / den, 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * ab), axis=1)


@dataclass
class Probe:
    """A ray against one primitive: t of the surface (the plane for triangles, the nearest
    positive root or the closest approach for spheres), whether the surface is reached within
    tolerance, and whether the ray passes within tolerance of the primitive's boundary."""

    t: np.ndarray
    reached: np.ndarray
    near_boundary: np.ndarray
    tol: np.ndarray
    boundary: np.ndarray  # distance of the ray's surface point to the boundary / rim


def _tolerance(d, t, q, rel):
    size = np.maximum(np.abs(q).max(axis=1), np.abs(t) * np.linalg.norm(d, axis=1))
    return rel * np.maximum(1.0, np.where(np.isfinite(size), size, 1.0))


def probe(prims, o, d, rel):
    n = len(prims.kind)
    t = np.full(n, np.inf)
    reached = np.zeros(n, bool)
    near = np.zeros(n, bool)
    tol = np.zeros(n)
    boundary = np.full(n, np.inf)
    tri = prims.kind == 1
    if tri.any():
        v = prims.tris[tri]
        oo, dd = o[tri], d[tri]
        nrm = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
        den = np.einsum("ij,ij->i", dd, nrm)
        with np.errstate(divide="ignore", invalid="ignore"):
            tt = np.einsum("ij,ij->i", v[:, 0] - oo, nrm) / den
        tt = np.where(np.isfinite(tt), tt, np.inf)
        q = oo + np.where(np.isfinite(tt), tt, 0)[:, None] * dd
        edge = np.min([_seg_dist(q, v[:, a], v[:, b]) for a, b in ((0, 1), (1, 2), (2, 0))],
                      axis=0)
        # Inside test by the signs of the sub-triangle normals.
        inside = np.ones(len(v), bool)
        for a, b in ((0, 1), (1, 2), (2, 0)):
            inside &= np.einsum("ij,ij->i", np.cross(v[:, b] - v[:, a], q - v[:, a]), nrm) >= 0
        tl = _tolerance(dd, tt, q, rel)
        t[tri] = tt
        tol[tri] = tl
        reached[tri] = (tt > 0) & np.isfinite(tt) & (inside | (edge <= tl))
        near[tri] = reached[tri] & (edge <= tl)
        boundary[tri] = edge
    sph = prims.kind == 0
    if sph.any():
        s = prims.spheres[sph]
        oo, dd = o[sph], d[sph]
        c, r = s[:, :3], s[:, 3]
        t0, t1 = sphere_roots(oo, dd, c, r)
        tt = np.where(t0 > 0, t0, np.where(t1 > 0, t1, np.nan))
        # Closest approach where the ray misses (or the sphere is behind).
        tc = np.einsum("ij,ij->i", c - oo, dd) / np.einsum("ij,ij->i", dd, dd)
        tt = np.where(np.isnan(tt), tc, tt)
        q = oo + tt[:, None] * dd
        perp = np.linalg.norm(np.cross(c - oo, dd), axis=1) / np.linalg.norm(dd, axis=1)
        tl = _tolerance(dd, tt, q, rel)
        t[sph] = tt
        tol[sph] = tl
        reached[sph] = (tt > 0) & (perp <= np.abs(r) + tl)
        near[sph] = reached[sph] & (np.abs(perp - np.abs(r)) <= tl)
        boundary[sph] = np.abs(perp - np.abs(r))
    return Probe(t, reached, near, tol, boundary)


def classify(o, d, lum, l_mapped, l_retri, orc, o_unmatched, rel):
    """Class name per differing pixel (see the module doc). `lum` and `orc` are the lumis and
    oracle primitives hit (Prims), `l_mapped` whether lumis's primitive has an oracle
    counterpart, `l_retri` whether it belongs to a polygon the two loaders triangulated
    differently, `o_unmatched` whether the oracle's triangle has no lumis counterpart."""
    n = len(o)
    out = np.full(n, "mismatch", object)
    a = probe(lum, o, d, rel)
    b = probe(orc, o, d, rel)
    dlen = np.linalg.norm(d, axis=1)
    l_kind, o_kind = lum.kind, orc.kind

    def rim(k):
        return "grazing" if k == 0 else "silhouette"

    for i in range(n):
        l_hit, o_hit = l_kind[i] >= 0, o_kind[i] >= 0
        if l_hit and not a.reached[i]:
            out[i] = "mismatch" if l_mapped[i] or l_retri[i] else "unmapped"
            continue  # lumis reports a primitive the ray does not reach
        if l_hit and o_hit:
            tol = max(a.tol[i], b.tol[i])
            if abs(a.t[i] - b.t[i]) * dlen[i] <= tol:
                if l_retri[i] and o_unmatched[i]:
                    out[i] = "retriangulated"
                elif a.near_boundary[i] or b.near_boundary[i]:
                    both_tri = l_kind[i] == 1 and o_kind[i] == 1
                    shared = both_tri and a.near_boundary[i] and b.near_boundary[i] and \
                        _share_edge(lum.tris[i], orc.tris[i], tol)
                    out[i] = "shared_edge" if shared else "edge"
                else:
                    out[i] = "tie"
            elif a.t[i] < b.t[i] and a.near_boundary[i]:
                out[i] = rim(l_kind[i])
            elif b.t[i] < a.t[i] and b.near_boundary[i]:
                out[i] = rim(o_kind[i])
        elif o_hit and b.near_boundary[i]:
            out[i] = rim(o_kind[i])
        elif l_hit and a.near_boundary[i]:
            out[i] = rim(l_kind[i])
        if out[i] == "mismatch" and l_hit and not (l_mapped[i] or l_retri[i]):
            out[i] = "unmapped"
    return out, a, b


def _share_edge(t1, t2, tol):
    """Whether two triangles have two corners in common (within `tol`, as the two loaders may
    round transformed vertices differently)."""
    same = (np.abs(t1[:, None, :] - t2[None, :, :]) <= tol).all(axis=2)
    return int(same.any(axis=1).sum()) >= 2
