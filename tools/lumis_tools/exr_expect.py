"""What lumis should have written where the oracle hit: the expected shading normal, and how far
the float32 limits of its hit points and the normal's curvature may move Z and N (the
per-pixel allowances of crosscheck_exr)."""

from __future__ import annotations

import numpy as np

# Relative error of lumis's float32 hit points against the coordinates they are computed from:
# triangle points interpolated from the corners (lumis's own bound gamma(7) ~ 7 ulps ~ 2^-21.2
# of the largest corner coordinate), sphere points projected in float64 then rounded, with Z
# computed from them in float32 (a few ulps of the point).
POS_EPS_TRIANGLE = 2.0 ** -21
POS_EPS_SPHERE = 2.0 ** -22


def expected_normals(geom, hits):
    """The shading normal lumis should report for each oracle hit (unit, world space)."""
    n = hits.normal.copy()
    tri = hits.kind == 1
    if tri.any():
        idx = hits.index[tri]
        vn = geom.vertex_normals[idx]  # (k, 3, 3)
        smooth = ~np.isnan(vn).any(axis=(1, 2))
        u, v = hits.u[tri], hits.v[tri]
        w = np.stack([1 - u - v, u, v], axis=1)
        s = np.einsum("kc,kcj->kj", w, np.nan_to_num(vn))
        length = np.linalg.norm(s, axis=1)
        ok = smooth & (length > 0)
        s = s / np.where(length > 0, length, 1)[:, None]
        ng = hits.normal[tri]
        s = np.where((np.einsum("ij,ij->i", s, ng) < 0)[:, None], -s, s)
        n[tri] = np.where(ok[:, None], s, ng)
    return n


def position_error(geom, hits, p):
    """Per oracle hit, how far lumis's float32 hit point may be off the surface: a few ulps of
    the largest corner coordinate for triangles (lumis interpolates the corners), of the hit
    point's own coordinates for spheres (lumis projects onto the sphere in float64)."""
    out = np.zeros(len(hits.kind))
    sph, tri = hits.kind == 0, hits.kind == 1
    out[sph] = POS_EPS_SPHERE * np.abs(p[sph]).max(axis=1)
    out[tri] = POS_EPS_TRIANGLE * np.abs(geom.triangles[hits.index[tri]]).max(axis=(1, 2))
    return out


def normal_rate(geom, hits):
    """Per oracle hit, how fast the expected normal turns per unit of distance along the
    surface: 1/r on spheres, 0 on flat triangles, and on smooth ones the largest difference of
    two corner normals over their distance, divided by the length of the interpolated
    (unnormalised) normal."""
    k = np.zeros(len(hits.kind))
    sph = hits.kind == 0
    k[sph] = 1.0 / np.abs(geom.spheres[hits.index[sph], 3])
    tri = hits.kind == 1
    if tri.any():
        idx = hits.index[tri]
        v, vn = geom.triangles[idx], geom.vertex_normals[idx]
        smooth = ~np.isnan(vn).any(axis=(1, 2))
        vn = np.nan_to_num(vn)
        rate = np.zeros(len(idx))
        for a, b in ((0, 1), (1, 2), (2, 0)):
            dist = np.linalg.norm(v[:, a] - v[:, b], axis=1)
            rate = np.maximum(rate, np.linalg.norm(vn[:, a] - vn[:, b], axis=1)
                              / np.maximum(dist, 1e-300))
        u, w = hits.u[tri], hits.v[tri]
        s = np.einsum("kc,kcj->kj", np.stack([1 - u - w, u, w], axis=1), vn)
        length = np.linalg.norm(s, axis=1)
        k[tri] = np.where(smooth, rate / np.maximum(length, 1e-12), 0.0)
    return k
