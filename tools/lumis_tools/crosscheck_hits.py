#!/usr/bin/env python3
"""Cross-checks lumis's ray queries (in process through the Python package where installed,
plus one run of `lumis hits` that must agree bit for bit) against an independent oracle on
seeded ray sets.

    tools/crosscheck_hits.py SCENE_OR_MODEL [--rays-per-set N] [--report report.json]

The geometry is loaded without lumis (trimesh for OBJ/glTF with its scene graph, tomllib for
lumis TOML scenes, a parser here for the paper's .scn/.m); triangles are traced by Embree
(embreex, robust mode) and spheres by a float64 analytic test. Ray sets: incoherent rays through
the bounds, camera rays, grazing rays, rays leaving surfaces (secondary-like) and rays aimed
exactly at shared edges and vertices. lumis ids are mapped to the oracle's by triangle position.

Checks (exit 1 when one fails, 2 when it cannot check; thresholds on the command line):
  - loader: every lumis triangle/sphere has a counterpart and vice versa (polygons triangulated
    differently but covering the same area in the same plane are allowed and reported);
  - hit/miss agreement away from edges (default 100%): a disagreement counts as "near an edge"
    only when the hit point of whichever engine hit lies within 1e-5 x (|origin| + t|dir|) of an
    edge of its triangle, or of a sphere's silhouette;
  - primitive-id agreement where both hit away from edges (default >= 99.99%; the figure with
    edge rays is reported too); a retriangulated polygon hit at the same point, or two
    primitives hit at the same t at a shared edge, count as agreeing (both answers are right);
  - p99 of the relative t error where both hit the same primitive (default <= 1e-5), against
    the float64 distance to the primitive Embree (or the sphere test) chose; Embree's own
    float32 t is reported beside it;
  - unit normals of the same primitive agree (winding);
  - watertightness: no lumis ray aimed at a shared edge or vertex where the surface is crossed
    may pass through it (Embree's leaks there are counted and reported, not failed);
  - any-hit (occlusion) queries agree with closest-hit hit/miss away from edges.
Disagreements are classified as edge, grazing (|cos| < 1e-2 to the surface), coincident
(different primitives within 1e-5 relative t off edges) or other; see tools/README.md.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from . import exitcodes, lumis, rays as raysets
from .geometry import load_geometry
from .idmap import IdMap, snap_to_lumis
from .oracle import Oracle
from .prims import LumisPrims

EDGE_REL = 1e-5
GRAZING_COS = 1e-2
TIE_REL = 1e-6


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 2)[2])
    ap.add_argument("scene", type=Path, help=".toml, .scn, .obj, .gltf or .glb")
    ap.add_argument("--rays-per-set", type=int, default=4000,
                    help="rays in each of the five sets (default 4000)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--min-agreement-off-edge", type=float, default=100.0,
                    help="hit/miss agreement in %% over rays not near an edge (default 100)")
    ap.add_argument("--min-prim-agreement", type=float, default=99.99,
                    help="primitive-id agreement in %% where both hit (default 99.99)")
    ap.add_argument("--max-p99-rel-t", type=float, default=1e-5,
                    help="p99 of |t_lumis - t_oracle| / t_oracle (default 1e-5)")
    ap.add_argument("--lumis-args", default="",
                    help="extra `lumis hits` arguments, e.g. \"--accel bsp --traversal segments\"")
    ap.add_argument("--exact-samples", type=int, default=200,
                    help="hit/miss disagreements at triangle edges settled in exact rational "
                         "arithmetic (default 200)")
    ap.add_argument("--report", type=Path, help="write the JSON report here")
    ap.add_argument("--quiet", action="store_true", help="print only failures and the verdict")
    lumis.add_argument(ap)
    args = ap.parse_args(argv)
    lumis.use(args.lumis)

    try:
        report = crosscheck(args)
    except (exitcodes.SetupError, OSError) as e:  # the loader, lumis, or a file
        print(f"crosscheck_hits: {e}", file=sys.stderr)
        return exitcodes.SETUP
    if args.report:
        args.report.write_text(json.dumps(report, indent=2) + "\n")
    failures = report["failures"]
    name = args.scene
    if failures:
        for f in failures:
            print(f"FAIL {name}: {f}")
    else:
        s = report["summary"]
        print(f"ok   {name}: {s['rays']} rays, off-edge agreement {s['agreement_off_edge_pct']:.4f}%,"
              f" prim {s['prim_agreement_pct']:.4f}%, rel t p99 {s['rel_t']['p99']:.2e},"
              f" disagreements {s['disagreements']}")
    if not args.quiet:
        print(json.dumps(report["summary"], indent=2))
    return exitcodes.FAILED if failures else exitcodes.OK


def empty_scene_check(scene, n, seed, extra):
    """A scene with no primitives (a glTF scene without nodes): every ray must miss, closest
    and any hit alike. Nothing to compare Embree with; the rays fill the unit box."""
    rng = np.random.default_rng(seed)
    rays = np.zeros((n, 8), np.float32)
    rays[:, 0:3] = rng.uniform(-1, 1, (n, 3))
    d = rng.normal(size=(n, 3))
    rays[:, 3:6] = d / np.linalg.norm(d, axis=1, keepdims=True)
    rays[:, 7] = np.inf
    hit = int(np.isfinite(lumis.hits(scene, rays, extra=extra).t).sum())
    any_hit = int(np.isfinite(lumis.hits(scene, rays, any_hit=True, extra=extra).t).sum())
    failures = [f"{k} of {n} rays hit an empty scene ({what})"
                for k, what in ((hit, "closest hit"), (any_hit, "any hit")) if k]
    summary = {"rays": n, "agreement_off_edge_pct": 100.0 * (n - max(hit, any_hit)) / n,
               "prim_agreement_pct": 100.0, "rel_t": {"p99": 0.0},
               "disagreements": {"empty scene": hit + any_hit}}
    return {"scene": str(scene), "failures": failures, "summary": summary}


def crosscheck(args):
    scene = args.scene
    l_tris, l_spheres = lumis.primitives(scene)
    if len(l_tris) == 0 and len(l_spheres) == 0:
        return empty_scene_check(scene, args.rays_per_set, args.seed, args.lumis_args.split())
    g = load_geometry(scene)
    idmap = IdMap.build(g, l_tris, l_spheres)
    g, deviation = snap_to_lumis(g, idmap, l_tris, l_spheres)
    oracle = Oracle(g)
    rng = np.random.default_rng(args.seed)
    n = args.rays_per_set

    sets = {
        "incoherent": raysets.incoherent(g, n, rng),
        "camera": raysets.camera(g, n),
        "grazing": raysets.grazing(g, n, rng),
        "leaving_surfaces": raysets.leaving_surfaces(g, oracle, n, rng),
    }
    edge_rays, t_target, must_hit = raysets.edges_and_vertices(g, n, rng)
    sets["edges_vertices"] = edge_rays
    names = list(sets)
    label = np.concatenate([np.full(len(sets[k]), i) for i, k in enumerate(names)])
    rays = np.concatenate([sets[k] for k in names])
    edge_slice = slice(len(rays) - len(edge_rays), len(rays))

    extra = args.lumis_args.split()
    lh = lumis.hits(scene, rays, extra=extra)
    la = lumis.hits(scene, rays, any_hit=True, extra=extra)
    oh = oracle.trace(rays)

    aimed = np.zeros(len(rays), bool)
    near_target = lambda t: np.abs(t - t_target) <= 1e-4 * t_target  # noqa: E731
    aimed[edge_slice] = near_target(lh.t[edge_slice]) | near_target(oh.t[edge_slice])
    lumis_prims = LumisPrims(l_tris, l_spheres)
    a = analyse(g, lumis_prims, idmap, rays, lh, oh, aimed)
    l_hit, o_hit = np.isfinite(lh.t), np.isfinite(oh.t)
    any_disagree = np.isfinite(la.t) != o_hit
    any_off_edge = int(np.sum(any_disagree & ~a["near_edge"]))

    # Watertightness at shared edges and vertices crossed by the ray.
    seg = slice(edge_slice.start, edge_slice.stop)
    reach = t_target * (1 + 1e-5)
    lumis_leaks = int(np.sum(must_hit & ~(lh.t[seg] <= reach)))
    embree_leaks = int(np.sum(must_hit & ~(oh.t[seg] <= reach)))

    verdicts = exact_verdicts(rays, lh, oh, a, lumis_prims, g,
                              args.exact_samples)
    summary = {
        "scene": str(scene),
        "lumis_args": args.lumis_args,
        "seed": args.seed,
        "rays": int(len(rays)),
        "sets": {k: int(len(sets[k])) for k in names},
        "loader": {**idmap.summary(), "max_vertex_deviation": deviation, "lumis_triangles": int(len(l_tris)),
                   "oracle_triangles": int(len(g.triangles)),
                   "lumis_spheres": int(len(l_spheres)), "oracle_spheres": int(len(g.spheres))},
        "hits": {"lumis": int(l_hit.sum()), "oracle": int(o_hit.sum())},
        "agreement_pct": pct(np.sum(l_hit == o_hit), len(rays)),
        "agreement_off_edge_pct": pct(len(rays) - a["hitmiss_off_edge"], len(rays)),
        "prim_agreement_pct": pct(a["prim_agree"], a["both"]),
        "prim_agreement_incl_edges_pct": a["prim_agree_all_pct"],
        "rel_t": a["rel_t"],
        "normal_mismatches": a["normal_mismatches"],
        "any_hit_disagreements_off_edge": any_off_edge,
        "watertight": {"rays_crossing_at_edge_or_vertex": int(must_hit.sum()),
                       "lumis_leaks": lumis_leaks, "embree_leaks": embree_leaks},
        "disagreements": a["classes"],
        "edge_detail": a["edge_detail"],
        "edge_hit_miss_exact_verdicts": verdicts,
        "disagreements_by_set": {
            k: {c: int(np.sum((label == i) & (a["cls"] == c))) for c in a["classes"]}
            for i, k in enumerate(names)},
    }
    failures = []
    if lumis.package() is not None:
        # The queries above ran in process; one run through the binary keeps the command's own
        # path covered, and it must give the package's rows bit for bit.
        cli = lumis.hits(scene, rays, extra=extra, via="cli")
        if cli.rows.tobytes() != lh.rows.tobytes():
            failures.append("`lumis hits` and the Python package disagree on the same rays")
    if idmap.loader_mismatches():
        failures.append(f"loader: {idmap.loader_mismatches()} primitives without a counterpart "
                        f"({idmap.summary()})")
    if summary["agreement_off_edge_pct"] < args.min_agreement_off_edge:
        failures.append(f"hit/miss agreement off edges {summary['agreement_off_edge_pct']:.4f}% "
                        f"< {args.min_agreement_off_edge}%")
    if summary["prim_agreement_pct"] < args.min_prim_agreement:
        failures.append(f"primitive-id agreement {summary['prim_agreement_pct']:.4f}% "
                        f"< {args.min_prim_agreement}%")
    if a["rel_t"]["p99"] > args.max_p99_rel_t:
        failures.append(f"p99 relative t error {a['rel_t']['p99']:.3e} > {args.max_p99_rel_t}")
    if a["normal_mismatches"]:
        failures.append(f"{a['normal_mismatches']} hits on the same primitive with different "
                        "normals")
    if any_off_edge:
        failures.append(f"{any_off_edge} any-hit queries disagree with the oracle off edges")
    if lumis_leaks:
        failures.append(f"lumis leaks through {lumis_leaks} shared edges/vertices")
    examples = {c: [example(i, rays, lh, oh, a, names, label) for i in
                    np.flatnonzero(a["cls"] == c)[:10]]
                for c in ("edge", "grazing", "coincident", "other")}
    return {"summary": summary, "failures": failures, "examples": examples}


def pct(num, den):
    return 100.0 if den == 0 else float(100.0 * num / den)


def analyse(g, lumis_g, idmap, rays, lh, oh, aimed_at_edge):
    """Per-ray comparison; returns counts, percentiles and the class of each disagreement."""
    o = rays[:, 0:3].astype(np.float64)
    d = rays[:, 3:6].astype(np.float64)
    l_hit, o_hit = np.isfinite(lh.t), np.isfinite(oh.t)
    l_kind, l_idx = idmap.to_oracle(lh.prim)
    both = l_hit & o_hit
    same = both & (l_kind == oh.kind) & (l_idx == oh.index)

    # Geometry of each engine's hit, judged in float64 on the oracle's primitives.
    # lumis's hit is judged on lumis's own primitive (it may be a triangle the loader here
    # split differently), the oracle's on the oracle's.
    l_pk, l_pi = lumis_g.kind_index(lh.prim)
    near_l, graze_l = surface_flags(lumis_g.geometry, o, d, lh.t, l_pk, l_pi)
    near_o, graze_o = surface_flags(g, o, d, oh.t, oh.kind, oh.index)
    # A ray aimed at an edge or vertex of the oracle's mesh, answered there by either engine.
    near_edge = near_l | near_o | aimed_at_edge
    grazing = graze_l | graze_o
    with np.errstate(invalid="ignore"):
        rel = np.abs(lh.t - oh.t) / np.abs(oh.t)
    tie = both & (rel <= TIE_REL)
    cos_n = np.einsum("ij,ij->i", lh.normal, oh.normal)
    # Different primitives at the same t off edges are coincident surfaces (a cube resting on
    # a ground quad): both answers are right; lumis breaks exact ties by the lower primitive
    # index, Embree by traversal order.
    equivalent = same | tie

    hitmiss = l_hit != o_hit
    prim_diff = both & ~equivalent
    t_bad = same & (rel > 1e-4)
    disagree = hitmiss | prim_diff | t_bad
    cls = np.full(len(rays), "", dtype=object)
    coincident = both & tie & ~same
    cls[disagree & ~grazing] = "other"
    cls[disagree & grazing] = "grazing"
    cls[coincident] = "coincident"
    cls[(disagree | coincident) & near_edge] = "edge"
    classes = {c: int(np.sum(cls == c)) for c in ("edge", "grazing", "coincident", "other")}

    rel_t = percentiles(rel[same])
    with np.errstate(invalid="ignore"):
        rel_embree = np.abs(oh.t_embree - oh.t) / np.abs(oh.t)
    rel_t["embree_vs_float64"] = percentiles(rel_embree[same & (oh.kind == 1)])
    normal_mismatches = int(np.sum(same & (cos_n < 1 - 1e-4)))
    off = both & ~near_edge
    edge_detail = {
        "lumis_hit_oracle_missed": int(np.sum(near_edge & l_hit & ~o_hit)),
        "oracle_hit_lumis_missed": int(np.sum(near_edge & o_hit & ~l_hit)),
        "same_t_other_primitive": int(np.sum(near_edge & coincident)),
        "different_t": int(np.sum(near_edge & both & ~same & ~tie)),
    }
    return {"both": int(off.sum()), "edge_detail": edge_detail, "prim_agree": int(np.sum(off & equivalent)),
            "prim_agree_all_pct": pct(np.sum(both & equivalent), both.sum()),
            "hitmiss_off_edge": int(np.sum(hitmiss & ~near_edge)), "rel_t": rel_t,
            "normal_mismatches": normal_mismatches, "near_edge": near_edge, "cls": cls,
            "classes": classes}


def exact_verdicts(rays, lh, oh, a, lumis_prims, g, limit):
    """Settles up to `limit` hit/miss disagreements at triangle edges exactly: does the float32
    ray meet the float32 triangle the hitting engine reported (edges included), in rational
    arithmetic? Counts which engine was right."""
    from fractions import Fraction

    l_hit, o_hit = np.isfinite(lh.t), np.isfinite(oh.t)
    lk, li = lumis_prims.kind_index(lh.prim)
    picks = np.flatnonzero((l_hit != o_hit) & a["near_edge"]
                           & np.where(l_hit, lk == 1, oh.kind == 1))[:limit]
    out = {"settled": int(len(picks)), "lumis_right": 0, "embree_right": 0}
    for i in picks:
        tri = lumis_prims.geometry.triangles[li[i]] if l_hit[i] else g.triangles[oh.index[i]]
        q = [Fraction(float(x)) for x in rays[i, :6]]
        o, d = q[:3], q[3:]
        v = [[Fraction(float(x)) - o[k] for k, x in enumerate(p)] for p in tri]
        w = [det3(d, v[k], v[(k + 1) % 3]) for k in range(3)]
        crosses = (all(x >= 0 for x in w) or all(x <= 0 for x in w)) and any(w)
        if crosses:
            n = cross3([v[1][k] - v[0][k] for k in range(3)], [v[2][k] - v[0][k] for k in range(3)])
            den = sum(n[k] * d[k] for k in range(3))
            crosses = den != 0 and sum(n[k] * v[0][k] for k in range(3)) / den > 0
        right = "lumis_right" if bool(crosses) == bool(l_hit[i]) else "embree_right"
        out[right] += 1
    return out


def cross3(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def det3(a, b, c):
    return sum(x * y for x, y in zip(a, cross3(b, c)))


def percentiles(x):
    out = {"count": int(len(x))}
    for key, q in (("p50", 50), ("p99", 99), ("max", 100)):
        out[key] = float(np.percentile(x, q)) if len(x) else 0.0
    return out


def surface_flags(g, o, d, t, kind, index):
    """For rays whose hit (t, kind, index) is given: is the hit point within EDGE_REL x
    (|o| + t|d|) of an edge of its triangle (or of a sphere's silhouette), and is the ray
    grazing (|cos| to the surface normal < GRAZING_COS)? False where there is no hit."""
    near = np.zeros(len(o), bool)
    graze = np.zeros(len(o), bool)
    # Where an engine missed, judge the primitive the other one hit along the same ray: the
    # callers pass both engines' answers, so each ray gets both judgements.
    tri = (kind == 1) & (index >= 0) & np.isfinite(t)
    if tri.any():
        v = g.triangles[index[tri]]
        oo, dd = o[tri], d[tri]
        # The ray's closest approach to each edge segment, in float64.
        dist = np.min([segment_line_distance(oo, dd, v[:, k], v[:, (k + 1) % 3])
                       for k in range(3)], axis=0)
        scale = np.abs(oo).max(axis=1) + t[tri] * np.abs(dd).max(axis=1)
        near[tri] = dist <= EDGE_REL * scale
        n = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
        cos = np.abs(np.einsum("ij,ij->i", n, dd)) / (
            np.linalg.norm(n, axis=1) * np.linalg.norm(dd, axis=1) + 1e-300)
        graze[tri] = cos < GRAZING_COS
    sph = (kind == 0) & (index >= 0) & np.isfinite(t)
    if sph.any():
        s = g.spheres[index[sph]]
        oo, dd = o[sph], d[sph]
        f = oo - s[:, :3]
        du = dd / np.linalg.norm(dd, axis=1, keepdims=True)
        ell = np.linalg.norm(f - np.einsum("ij,ij->i", f, du)[:, None] * du, axis=1)
        scale = np.abs(oo).max(axis=1) + t[sph] * np.abs(dd).max(axis=1) + s[:, 3]
        near[sph] = np.abs(ell - s[:, 3]) <= EDGE_REL * scale
        graze[sph] = np.sqrt(np.maximum(0, 1 - (ell / s[:, 3]) ** 2)) < GRAZING_COS
    return near, graze


def segment_line_distance(o, d, a, b):
    """Distance between the line o + s d and the segment [a, b], per row, float64."""
    e = b - a
    w = o - a
    dd = np.einsum("ij,ij->i", d, d)
    ee = np.einsum("ij,ij->i", e, e)
    de = np.einsum("ij,ij->i", d, e)
    dw = np.einsum("ij,ij->i", d, w)
    ew = np.einsum("ij,ij->i", e, w)
    den = dd * ee - de * de
    with np.errstate(invalid="ignore", divide="ignore"):
        u = np.where(den > 1e-300 * dd * ee, (dd * ew - de * dw) / den, 0.0)
    u = np.clip(u, 0.0, 1.0)
    s = (de * u - dw) / dd
    p_line = o + s[:, None] * d
    p_seg = a + u[:, None] * e
    return np.linalg.norm(p_line - p_seg, axis=1)


def example(i, rays, lh, oh, a, names, label):
    return {"ray": [float(x) for x in rays[i]], "set": names[label[i]],
            "class": a["cls"][i],
            "lumis": {"t": float(lh.t[i]), "prim": int(lh.prim[i])},
            "oracle": {"t": float(oh.t[i]), "kind": int(oh.kind[i]), "index": int(oh.index[i])}}


def cli():
    exitcodes.run(main, prog="crosscheck_hits")


if __name__ == "__main__":
    cli()
