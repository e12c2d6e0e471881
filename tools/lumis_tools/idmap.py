"""Maps lumis primitive ids to the oracle's triangle and sphere indices by position, so neither
side has to keep the other's primitive order (loaders may order, split or instance meshes
differently; only the geometry has to agree)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .geometry import Geometry


@dataclass
class IdMap:
    """`kind[p]`, `index[p]`: the oracle primitive (0 sphere / 1 triangle, index) that lumis
    primitive `p` is, or -1 when it matched nothing. `flipped` counts lumis triangles that match
    an oracle triangle only with the opposite winding (they map, but are reported)."""

    kind: np.ndarray
    index: np.ndarray
    tolerance: float
    unmatched_lumis_triangles: int
    unmatched_oracle_triangles: int
    unmatched_lumis_spheres: int
    unmatched_oracle_spheres: int
    flipped: int
    # Unmatched triangles explained as a different triangulation of the same polygons: in each
    # plane, the unmatched lumis and oracle triangles cover the same area (e.g. lumis ear-clips
    # a concave polygon that trimesh fans from a vertex that sees all of it).
    retriangulated_lumis: int = 0
    retriangulated_oracle: int = 0
    lumis_retriangulated: np.ndarray | None = None  # bool per lumis primitive id

    def to_oracle(self, prims):
        """(kind, index) per lumis primitive id (-1 for -1 or unmatched ids)."""
        prims = np.asarray(prims, np.int64)
        ok = (prims >= 0) & (prims < len(self.kind))
        kind = np.full(prims.shape, -1, np.int64)
        index = np.full(prims.shape, -1, np.int64)
        kind[ok] = self.kind[prims[ok]]
        index[ok] = self.index[prims[ok]]
        return kind, index

    def summary(self):
        return {k: getattr(self, k) for k in (
            "tolerance", "unmatched_lumis_triangles", "unmatched_oracle_triangles",
            "unmatched_lumis_spheres", "unmatched_oracle_spheres", "flipped",
            "retriangulated_lumis", "retriangulated_oracle")}

    def loader_mismatches(self):
        """Primitives on either side with no counterpart, beyond retriangulated polygons."""
        return (self.unmatched_lumis_triangles - self.retriangulated_lumis
                + self.unmatched_oracle_triangles - self.retriangulated_oracle
                + self.unmatched_lumis_spheres + self.unmatched_oracle_spheres)

    @staticmethod
    def build(geometry: Geometry, lumis_tris: np.ndarray, lumis_spheres: np.ndarray,
              rel_tol=1e-5):
        """Matches within `rel_tol` of the extent of the triangles (for triangles) or of each
        sphere's own size and position (for spheres), per coordinate."""
        pts = geometry.triangles.reshape(-1, 3)
        extent = float(np.max(pts.max(0) - pts.min(0))) if len(pts) else 0.0
        tol = rel_tol * max(extent, 1e-30)
        total = int(max([-1, *lumis_tris[:, 0], *lumis_spheres[:, 0]])) + 1
        kind = np.full(total, -1, np.int64)
        index = np.full(total, -1, np.int64)

        l_ids = lumis_tris[:, 0].astype(np.int64)
        l_tris = lumis_tris[:, 1:].astype(np.float64).reshape(-1, 3, 3)
        match, flipped = _match_triangles(l_tris, geometry.triangles, tol)
        kind[l_ids[match >= 0]] = 1
        index[l_ids[match >= 0]] = match[match >= 0]

        s_ids = lumis_spheres[:, 0].astype(np.int64)
        s_match = _match_spheres(lumis_spheres[:, 1:].astype(np.float64), geometry.spheres,
                                 rel_tol)
        kind[s_ids[s_match >= 0]] = 0
        index[s_ids[s_match >= 0]] = s_match[s_match >= 0]
        taken = np.zeros(len(geometry.triangles), bool)
        taken[match[match >= 0]] = True
        l_left, o_left = _same_area_per_plane(l_tris[match < 0], geometry.triangles[~taken], tol)
        retri = np.zeros(total, bool)
        retri[l_ids[np.flatnonzero(match < 0)[l_left]]] = True
        return IdMap(
            kind, index, tol,
            int(np.sum(match < 0)), len(geometry.triangles) - int(np.sum(match >= 0)),
            int(np.sum(s_match < 0)), len(geometry.spheres) - int(np.sum(s_match >= 0)),
            int(flipped), int(l_left.sum()), int(o_left.sum()), retri)


def _canonical(tris, tol, reverse=False):
    """Each triangle rotated (winding kept) to start at its smallest vertex, in grid units."""
    if reverse:
        tris = tris[:, [0, 2, 1]]
    q = np.round(tris / tol).astype(np.int64)
    # Lexicographic rank of the three vertices: pick the smallest as the start.
    order = np.zeros(len(q), np.int64)
    best = q[:, 0]
    for k in (1, 2):
        cand = q[:, k]
        less = np.zeros(len(q), bool)
        decided = np.zeros(len(q), bool)
        for axis in range(3):
            lt = (cand[:, axis] < best[:, axis]) & ~decided
            gt = (cand[:, axis] > best[:, axis]) & ~decided
            less |= lt
            decided |= lt | gt
        order = np.where(less, k, order)
        best = np.where(less[:, None], cand, best)
    rot = (order[:, None] + np.arange(3)[None, :]) % 3
    return np.take_along_axis(q, rot[:, :, None], axis=1).reshape(len(q), 9)


def _pair_equal_keys(a, b):
    """Pairs equal rows of int arrays `a` and `b` one to one (duplicates pair up in order):
    returns for each row of `a` the matching row of `b` or -1."""
    out = np.full(len(a), -1, np.int64)
    if not len(a) or not len(b):
        return out
    both = np.concatenate([a, b])
    _, group = np.unique(both, axis=0, return_inverse=True)
    group = group.ravel()
    src = np.r_[np.zeros(len(a), np.int64), np.ones(len(b), np.int64)]
    idx = np.r_[np.arange(len(a)), np.arange(len(b))]
    order = np.lexsort((idx, src, group))
    g, s, i = group[order], src[order], idx[order]
    # Rank of each entry within its (group, source) run.
    run_start = np.r_[True, (g[1:] != g[:-1]) | (s[1:] != s[:-1])]
    starts = np.flatnonzero(run_start)
    rank = np.arange(len(g)) - np.repeat(starts, np.diff(np.r_[starts, len(g)]))
    key_b = g[s == 1] * (len(both) + 1) + rank[s == 1]
    key_a = g[s == 0] * (len(both) + 1) + rank[s == 0]
    sorter = np.argsort(key_b)
    pos = np.searchsorted(key_b, key_a, sorter=sorter)
    pos = np.minimum(pos, len(key_b) - 1)
    found = key_b[sorter[pos]] == key_a
    out[i[s == 0][found]] = i[s == 1][sorter[pos[found]]]
    return out


def _match_triangles(l_tris, o_tris, tol):
    """For each lumis triangle the oracle triangle at the same place (-1 if none), and how many
    matched only with reversed winding. Exact grid keys first; the few that straddle a grid
    cell boundary are matched by distance."""
    match = _pair_equal_keys(_canonical(l_tris, tol), _canonical(o_tris, tol))
    flipped = 0
    taken = np.zeros(len(o_tris), bool)
    taken[match[match >= 0]] = True
    left_l = np.flatnonzero(match < 0)
    if len(left_l):
        left_o = np.flatnonzero(~taken)
        flip = _pair_equal_keys(_canonical(l_tris[left_l], tol, reverse=True),
                                _canonical(o_tris[left_o], tol))
        ok = flip >= 0
        match[left_l[ok]] = left_o[flip[ok]]
        taken[left_o[flip[ok]]] = True
        flipped += int(ok.sum())
    left_l = np.flatnonzero(match < 0)
    for i in left_l[:10_000]:  # a loader that disagrees wholesale is reported, not searched
        left_o = np.flatnonzero(~taken)
        if not len(left_o):
            break
        cand = o_tris[left_o]
        best, best_j, best_flip = np.inf, -1, False
        for rev in (False, True):
            t = l_tris[i][[0, 2, 1]] if rev else l_tris[i]
            for r in range(3):
                d = np.abs(cand - np.roll(t, r, axis=0)[None]).max(axis=(1, 2))
                j = int(np.argmin(d))
                if d[j] < best:
                    best, best_j, best_flip = d[j], j, rev
        if best <= tol:
            match[i] = left_o[best_j]
            taken[left_o[best_j]] = True
            flipped += best_flip
    return match, flipped


def _match_spheres(a, b, rel_tol):
    """For each sphere (centre, radius) of `a` the sphere of `b` within `rel_tol` of its radius
    and centre magnitude in every column (-1 if none), one to one. Exact float32 equality
    first (the common case), then by distance."""
    out = _pair_equal_keys(a.view(np.int64), b.view(np.int64))
    taken = np.zeros(len(b), bool)
    taken[out[out >= 0]] = True
    for i in np.flatnonzero(out < 0)[:10_000]:
        free = np.flatnonzero(~taken)
        if not len(free):
            break
        d = np.abs(b[free] - a[i]).max(axis=1)
        j = int(np.argmin(d))
        if d[j] <= rel_tol * max(a[i, 3], np.abs(a[i, :3]).max()):
            out[i] = free[j]
            taken[free[j]] = True
    return out


def _same_area_per_plane(a, b, tol):
    """Which triangles of `a` and `b` lie in planes where both sets cover the same total area
    (within a relative 1e-6): (mask over a, mask over b)."""
    def planes(t):
        n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
        area = 0.5 * np.linalg.norm(n, axis=1)
        unit = n / np.maximum(2 * area, 1e-300)[:, None]
        offset = np.einsum("ij,ij->i", unit, t[:, 0])
        key = np.round(np.c_[unit * 1e4, offset / tol]).astype(np.int64)
        return [tuple(k) for k in key], area

    ka, area_a = planes(a)
    kb, area_b = planes(b)
    sum_a, sum_b = {}, {}
    for k, ar in zip(ka, area_a):
        sum_a[k] = sum_a.get(k, 0.0) + ar
    for k, ar in zip(kb, area_b):
        sum_b[k] = sum_b.get(k, 0.0) + ar
    same = {k for k in sum_a if k in sum_b and abs(sum_a[k] - sum_b[k]) <= 1e-6 * sum_a[k]}
    return (np.array([k in same for k in ka], bool), np.array([k in same for k in kb], bool))


def snap_to_lumis(geometry: Geometry, idmap: IdMap, lumis_tris, lumis_spheres):
    """A copy of `geometry` whose matched primitives take lumis's exact float32 coordinates,
    and the largest coordinate change that made.

    Matching already proved the loaders agree to `idmap.tolerance`; what is left are float32
    roundings of transforms done in a different order (lumis in f32, the loader here in f64),
    which move a hit by ~1e-7 relative. Tracing the bit-identical primitives keeps that out of
    the intersection comparison, whose t errors are then the engines' own."""
    import copy

    g = copy.copy(geometry)
    g.triangles = geometry.triangles.copy()
    g.spheres = geometry.spheres.copy()
    deviation = 0.0
    for rows, target, kind, width in ((lumis_tris, g.triangles, 1, 9),
                                      (lumis_spheres, g.spheres, 0, 4)):
        if not len(rows):
            continue
        ids = rows[:, 0].astype(np.int64)
        ok = (idmap.kind[ids] == kind) & (idmap.index[ids] >= 0)
        dst = idmap.index[ids[ok]]
        src = rows[ok, 1:].astype(np.float64).reshape((-1, *target.shape[1:]))
        if kind == 1:
            # Keep the oracle's vertex order (rotations and flips differ); move each vertex to
            # the nearest lumis vertex of the same triangle.
            old = target[dst]
            dist = np.linalg.norm(old[:, :, None, :] - src[:, None, :, :], axis=-1)
            src = np.take_along_axis(src, dist.argmin(axis=2)[:, :, None], axis=1)
        if len(dst):
            deviation = max(deviation, float(np.abs(target[dst] - src).max()))
        target[dst] = src
    return g, deviation
