"""Every seeded ray set the tools trace: the cross-checks' five (incoherent, camera, grazing,
leaving surfaces, edges and vertices) and the Embree benchmark's three (around the box, an
orbit camera, all-miss). Every set is float32 `(N, 8)` rays (origin, direction, t_min = 0,
t_max = inf), plus per-ray extras some checks need.

All origins and directions are computed in float64 and rounded to float32 once, so both engines
trace exactly the same rays."""

from __future__ import annotations

import math

import numpy as np

from .geometry import Geometry


def pack(origins, dirs):
    rays = np.zeros((len(origins), 8), np.float32)
    rays[:, 0:3] = origins
    rays[:, 3:6] = dirs
    rays[:, 7] = np.inf
    return rays


def focus_bounds(g: Geometry):
    """Bounds of where the scene's detail is: the 0.5-99.5 percentile box of primitive centres,
    padded, so one huge ground sphere does not make every ray miss everything else."""
    centres = [g.triangles.mean(axis=1), g.spheres[:, :3]]
    sizes = [np.ptp(g.triangles, axis=1).max(axis=1), 2 * g.spheres[:, 3]]
    centres = np.concatenate(centres)
    sizes = np.concatenate(sizes)
    lo = np.percentile(centres, 0.5, axis=0)
    hi = np.percentile(centres, 99.5, axis=0)
    pad = 0.05 * np.max(hi - lo) + np.median(sizes)
    return lo - pad, hi + pad


def unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def random_dirs(rng, n):
    return unit(rng.normal(size=(n, 3)))


def incoherent(g, n, rng):
    """Origins on a sphere around the focus bounds, aimed at random points inside them."""
    lo, hi = focus_bounds(g)
    centre, radius = (lo + hi) / 2, 0.75 * np.linalg.norm(hi - lo) + 1e-30
    origins = centre + radius * random_dirs(rng, n)
    targets = rng.uniform(lo, hi, size=(n, 3))
    return pack(origins, targets - origins)


def camera(g, n):
    """A pinhole grid of about `n` rays: the scene's camera if it has one, else a three-quarter
    view of the focus bounds."""
    lo, hi = focus_bounds(g)
    if g.camera is not None:
        eye, at, up = g.camera.position, g.camera.look_at, g.camera.up
        fov = g.camera.fov or 40.0
    else:
        centre, size = (lo + hi) / 2, np.linalg.norm(hi - lo)
        eye, at, up, fov = centre + size * np.array([0.6, 0.45, 0.9]), centre, np.r_[0, 1, 0], 40
    side = max(1, int(np.sqrt(n)))
    w = unit(at - eye)
    u = unit(np.cross(w, up))
    v = np.cross(u, w)
    h = np.tan(np.radians(fov) / 2)
    s = (np.arange(side) + 0.5) / side * 2 - 1
    x, y = np.meshgrid(s * h, -s * h)
    dirs = w + x.reshape(-1, 1) * u + y.reshape(-1, 1) * v
    return pack(np.broadcast_to(eye, dirs.shape), dirs)


def grazing(g, n, rng):
    """Rays crossing a random triangle's interior at 1e-6 to 1e-2 rad from its plane, and rays
    passing a random sphere at 1e-7 to 1e-2 of its radius inside or outside its silhouette."""
    lo, hi = focus_bounds(g)
    length = 0.5 * np.linalg.norm(hi - lo) + 1e-30
    parts = []
    n_tri = n if not len(g.spheres) else (n // 2 if len(g.triangles) else 0)
    if n_tri and len(g.triangles):
        t = g.triangles[rng.integers(len(g.triangles), size=n_tri)]
        bary = rng.dirichlet([1, 1, 1], size=n_tri)
        p = np.einsum("ij,ijk->ik", bary, t)
        normal = unit(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]))
        tangent = unit(np.cross(normal, random_dirs(rng, n_tri)))
        angle = 10 ** rng.uniform(-6, -2, n_tri) * rng.choice([-1, 1], n_tri)
        d = np.cos(angle)[:, None] * tangent + np.sin(angle)[:, None] * normal
        parts.append(pack(p - length * d, d))
    n_sph = n - n_tri
    if n_sph and len(g.spheres):
        s = g.spheres[rng.integers(len(g.spheres), size=n_sph)]
        d = random_dirs(rng, n_sph)
        e = unit(np.cross(d, random_dirs(rng, n_sph)))
        rel = 10 ** rng.uniform(-7, -2, n_sph) * rng.choice([-1, 1], n_sph)
        ell = s[:, 3] * (1 + rel)
        back = 2 * s[:, 3] + length
        parts.append(pack(s[:, :3] + ell[:, None] * e - back[:, None] * d, d))
    return np.concatenate(parts) if parts else np.zeros((0, 8), np.float32)


def leaving_surfaces(g, oracle, n, rng):
    """Secondary-like rays: from the hits of incoherent rays, origins offset 1e-5 (relative to
    the hit point's magnitude) along the normal to the side the ray came from, leaving as a
    mirror reflection or at random into that hemisphere; a quarter leave through the surface
    (refraction-like), offset to the other side."""
    first = incoherent(g, 3 * n, rng)
    h = oracle.trace(first)
    hit = np.flatnonzero(np.isfinite(h.t))[:n]
    if not len(hit):
        return np.zeros((0, 8), np.float32)
    o = first[hit, 0:3].astype(np.float64)
    d = first[hit, 3:6].astype(np.float64)
    p = o + h.t[hit, None] * d
    nrm = h.normal[hit]
    side = -np.sign(np.einsum("ij,ij->i", d, nrm))[:, None]
    side[side == 0] = 1
    through = rng.random(len(hit)) < 0.25
    side = np.where(through[:, None], -side, side)
    eps = 1e-5 * np.maximum(np.abs(p).max(axis=1), 1e-3 * np.linalg.norm(np.ptp(p, axis=0)))
    origin = p + side * eps[:, None] * nrm
    du = unit(d)
    mirror = du - 2 * np.einsum("ij,ij->i", du, nrm)[:, None] * nrm
    rand = random_dirs(rng, len(hit))
    rand *= np.sign(np.einsum("ij,ij->i", rand, side * nrm))[:, None]
    use_mirror = (rng.random(len(hit)) < 0.5) & ~through
    dirs = np.where(use_mirror[:, None], mirror, rand)
    return pack(origin, dirs)


def edges_and_vertices(g, n, rng):
    """Rays aimed exactly (before float32 rounding) at points of shared triangle edges and at
    shared vertices, from random directions at least 5 degrees off every adjacent face's plane.
    Returns (rays, expected t along each ray to its target, must_hit): `must_hit` marks rays
    that cross the surface there (every face around the target faces the ray the same way), so
    a watertight tracer has to hit at or before the target."""
    empty = (np.zeros((0, 8), np.float32), np.zeros(0), np.zeros(0, bool))
    if not len(g.triangles) or not n:
        return empty
    lo, hi = focus_bounds(g)
    length = 0.5 * np.linalg.norm(hi - lo) + 1e-30
    tris = g.triangles
    normals = unit(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]) + 1e-300)
    # Edges keyed by their two endpoints (exact float32 values), unordered.
    a = tris.reshape(-1, 3)
    b = tris[:, [1, 2, 0]].reshape(-1, 3)
    lo_end = np.where(_lex_less(a, b)[:, None], a, b)
    hi_end = np.where(_lex_less(a, b)[:, None], b, a)
    keys = np.c_[lo_end, hi_end]
    _, edge_id, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    edge_id = edge_id.ravel()
    shared = np.flatnonzero(counts[edge_id] == 2)  # half-edge indices of manifold edges
    pool = shared if len(shared) else np.arange(len(a))
    n_edge = n // 2 if len(shared) else n
    pick = rng.choice(pool, size=n_edge)
    s = rng.uniform(0.05, 0.95, n_edge)
    s[: n_edge // 4] = 0.5
    targets = a[pick] + s[:, None] * (b[pick] - a[pick])
    faces_of_edge = _members(edge_id, edge_id[pick])
    # Vertices: corners of random triangles.
    n_vert = n - n_edge
    vt = rng.integers(len(tris), size=n_vert)
    corner = rng.integers(3, size=n_vert)
    vtargets = tris[vt, corner]
    vkeys, vinv = np.unique(a, axis=0, return_inverse=True)
    vinv = vinv.ravel()
    # A vertex on an open boundary can be passed by a ray without crossing the surface.
    on_boundary = np.zeros(len(vkeys), bool)
    boundary_half_edges = np.flatnonzero(counts[edge_id] == 1)
    on_boundary[vinv[boundary_half_edges]] = True
    next_corner = (boundary_half_edges // 3) * 3 + (boundary_half_edges % 3 + 1) % 3
    on_boundary[vinv[next_corner]] = True
    vertex_faces = _members(vinv, vinv[vt * 3 + corner])
    interior = np.r_[counts[edge_id[pick]] == 2, ~on_boundary[vinv[vt * 3 + corner]]]
    targets = np.concatenate([targets, vtargets])
    faces = faces_of_edge + vertex_faces
    dirs = np.zeros_like(targets)
    must = np.zeros(len(targets), bool)
    for i, f in enumerate(faces):
        fn = normals[f]
        for _ in range(20):
            d = random_dirs(rng, 1)[0]
            cos = fn @ d
            if np.all(np.abs(cos) > np.sin(np.radians(5))):
                break
        dirs[i] = d
        must[i] = interior[i] and (np.all(cos > 0) or np.all(cos < 0))
    origins = targets - length * dirs
    rays = pack(origins, dirs)
    # Distance to the target along the float32 ray.
    o32 = rays[:, 0:3].astype(np.float64)
    d32 = rays[:, 3:6].astype(np.float64)
    t_target = np.einsum("ij,ij->i", targets - o32, d32) / np.einsum("ij,ij->i", d32, d32)
    return rays, t_target, must


def _members(group_of, groups):
    """For each group in `groups`, the triangles (half-edge or corner index // 3) in it."""
    order = np.argsort(group_of, kind="stable")
    sorted_groups = group_of[order]
    start = np.searchsorted(sorted_groups, groups, "left")
    end = np.searchsorted(sorted_groups, groups, "right")
    return [order[s:e] // 3 for s, e in zip(start, end)]


def _lex_less(a, b):
    """Row-wise lexicographic a < b."""
    out = np.zeros(len(a), bool)
    decided = np.zeros(len(a), bool)
    for k in range(3):
        lt = (a[:, k] < b[:, k]) & ~decided
        gt = (a[:, k] > b[:, k]) & ~decided
        out |= lt
        decided |= lt | gt
    return out


# ---------------------------------------------------------------------------------------------
# The Embree benchmark's sets (tools/lumis_tools/bench_embree.py), on a bounding box: seeded by
# their own generator, so the benchmark's figures stay comparable between versions.

BENCH_CAMERA_FOV_DEG = 40.0


def unit_rays(origins, dirs):
    """float32 (N, 8) rays with unit directions, t in [0, inf)."""
    return pack(origins, unit(dirs))


def bench_incoherent(lo, hi, n, seed):
    """Origins on a sphere of twice the bounding radius, aimed at uniform points of the box."""
    rng = np.random.default_rng(seed)
    centre, radius = (lo + hi) / 2, np.linalg.norm(hi - lo) / 2
    on_sphere = rng.normal(size=(n, 3))
    on_sphere /= np.linalg.norm(on_sphere, axis=1, keepdims=True)
    origins = centre + 2 * radius * on_sphere
    targets = lo + rng.random((n, 3)) * (hi - lo)
    return unit_rays(origins, targets - origins)


def bench_all_miss(lo, hi, n, seed):
    """The incoherent origins, each pointing straight away from the model: every ray misses
    the root box, so its time is the per-ray fixed cost (ray set-up, root test, hit record)."""
    rays = bench_incoherent(lo, hi, n, seed)
    centre = (lo + hi) / 2
    rays[:, 3:6] = unit_rays(rays[:, 0:3], rays[:, 0:3] - centre)[:, 3:6]
    return rays


def bench_camera(points, width, height):
    """Pinhole grid from azimuth 45 degrees, elevation 30 degrees (y up), aimed at the middle of
    the model's outline and at the nearest distance (plus 2%) that keeps every vertex in the
    frame."""
    az, el = math.radians(45), math.radians(30)
    back = np.array([math.sin(az) * math.cos(el), math.sin(el), math.cos(az) * math.cos(el)])
    forward = -back
    right = np.cross(forward, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    x, y = points @ right, points @ up
    centre = (points.min(0) + points.max(0)) / 2
    centre += ((x.min() + x.max()) / 2 - centre @ right) * right
    centre += ((y.min() + y.max()) / 2 - centre @ up) * up
    tan_v = math.tan(math.radians(BENCH_CAMERA_FOV_DEG) / 2)
    tan_h = tan_v * width / height
    rel = points - centre
    need = rel @ back + np.maximum(np.abs(rel @ right) / tan_h, np.abs(rel @ up) / tan_v)
    eye = centre + back * need.max() * 1.02
    xs = ((np.arange(width) + 0.5) / width * 2 - 1) * tan_h
    ys = (1 - (np.arange(height) + 0.5) / height * 2) * tan_v
    gx, gy = np.meshgrid(xs, ys)
    dirs = forward + gx.reshape(-1, 1) * right + gy.reshape(-1, 1) * up
    return unit_rays(np.broadcast_to(eye, dirs.shape), dirs)
