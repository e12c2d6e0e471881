"""SCENE mode of crosscheck_exr: render, check the EXR's layout, header and AOV contract, then
its Z, N and id layers against the oracle, pixel by pixel (see crosscheck_exr's doc)."""

from __future__ import annotations

import json
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

from . import lumis as lumis_bin
from .exr_camera import camera_rays
from .exr_classify import CLASSES, SAME_DEPTH, classify
from .exr_expect import expected_normals, normal_rate, position_error
from .exr_file import RGBA, Checks, check_header, check_layout, read_exr, write_layers
from .idiff import EXIT_FAIL, EXIT_OK, EXIT_WARN, STATUS, ToolError, channel_stats, threshold_for
from .prims import LumisPrims, Prims


def render(scene, out, args):
    cmd = ["render", scene, "-o", out, "--width", args.width, "--height", args.height,
           "--spp", args.spp, "--quiet"]
    if args.float:
        cmd.append("--float")
    for extra in args.render_arg or []:
        cmd.append(extra)
    try:
        lumis_bin.run(cmd, "lumis render")
    except lumis_bin.LumisError as e:
        raise ToolError(str(e)) from e


def check_scene(scene, args, fail_spec, warn_spec, diff_path):
    from .geometry import LoadError, load_geometry
    from .idmap import IdMap, snap_to_lumis
    from .oracle import Oracle

    t_start = time.perf_counter()
    timings = {}
    report = {"scene": str(scene)}
    checks = Checks()
    report["checks"] = checks.items
    with tempfile.TemporaryDirectory(prefix="crosscheck-exr-") as tmp:
        if args.exr:
            exr_path = Path(args.exr)
            spp = None
        else:
            exr_path = Path(tmp) / "render.exr"
            if args.keep_exr:
                Path(args.keep_exr).mkdir(parents=True, exist_ok=True)
                exr_path = Path(args.keep_exr) / (Path(scene).name + ".exr")
            t0 = time.perf_counter()
            render(scene, exr_path, args)
            timings["render_s"] = time.perf_counter() - t0
            spp = args.spp
        report["exr"] = str(exr_path)
        exr = read_exr(exr_path)
    width, height = exr.size
    expect_w = width if args.exr else args.width
    expect_h = height if args.exr else args.height
    report["size"] = [width, height]
    complete = check_layout(exr, expect_w, expect_h, args.float, checks)
    w2c, w2ndc = check_header(exr.spec, spp, checks)
    if not complete or w2c is None or w2ndc is None:
        return finish(report, checks, {}, t_start, timings)

    px = exr.pixels
    z, prim, obj = px["Z"], px["id.prim"], px["id.object"]
    nrm = np.stack([px["N.X"], px["N.Y"], px["N.Z"]], axis=-1)

    # AOV value contract.
    miss = prim == -1
    hit = ~miss
    report["pixels"] = {"total": int(z.size), "lumis_hits": int(hit.sum())}
    checks.add("ids are integers >= -1", np.all((prim == np.round(prim)) & (prim >= -1))
               and np.all((obj == np.round(obj)) & (obj >= -1)), "")
    checks.add("misses: Z = +inf, N = 0, id.object = -1",
               np.all(np.isposinf(z[miss])) and np.all(nrm[miss] == 0)
               and np.all(obj[miss] == -1), f"{int(miss.sum())} misses")
    checks.add("hits: Z finite > 0", np.all(np.isfinite(z[hit]) & (z[hit] > 0)),
               f"{int(np.sum(~(np.isfinite(z[hit]) & (z[hit] > 0))))} bad")
    nlen = np.linalg.norm(nrm[hit].astype(np.float64), axis=-1)
    checks.add("hits: |N| = 1", np.all(np.abs(nlen - 1) <= 1e-5),
               f"max ||N| - 1| {np.abs(nlen - 1).max() if nlen.size else 0:.2e}")
    checks.add("hits: id.object >= 0", np.all(obj[hit] >= 0), "")
    pairs = np.unique(np.stack([prim[hit], obj[hit]], 1), axis=0)
    checks.add("one object id per primitive", len(pairs) == len(np.unique(pairs[:, 0])),
               f"{len(np.unique(pairs[:, 0]))} primitives, {len(pairs)} (prim, object) pairs")
    rgba_nan = sum(int(np.isnan(px[c]).sum()) for c in RGBA)
    checks.add("RGBA has no NaN", rgba_nan == 0, f"{rgba_nan} NaN samples")

    cam = camera_rays(w2c, w2ndc, width, height, checks)

    # The oracle, on the independently loaded geometry. Primitives matched to lumis's take its
    # exact float32 coordinates (snap_to_lumis), so that one-ulp differences between the two
    # loaders' transforms stay out of the comparison; the largest such move is reported.
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            # trimesh's texture handling warns about NaN medians on untextured glTF; noise.
            warnings.simplefilter("ignore", RuntimeWarning)
            geom = load_geometry(scene)
    except (LoadError, OSError) as e:
        raise ToolError(f"{scene}: the independent loader failed: {e}") from e
    try:
        l_tris, l_spheres = lumis_bin.primitives(scene)
    except lumis_bin.LumisError as e:
        raise ToolError(str(e)) from e
    idmap = IdMap.build(geom, l_tris, l_spheres)
    geom, deviation = snap_to_lumis(geom, idmap, l_tris, l_spheres)
    lprims = LumisPrims(l_tris, l_spheres)
    timings["load_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    hits = Oracle(geom).trace(cam.rays)
    timings["oracle_s"] = time.perf_counter() - t0
    report["geometry"] = {"triangles": len(geom.triangles), "spheres": len(geom.spheres),
                          "smooth_triangles": int((~np.isnan(geom.vertex_normals)
                                                   .any(axis=(1, 2))).sum()),
                          "normal_mapped_triangles": int(geom.triangle_normal_mapped.sum()),
                          "normal_mapped_spheres": int(geom.sphere_normal_mapped.sum()),
                          "lumis_triangles": len(l_tris), "lumis_spheres": len(l_spheres)}
    report["idmap"] = {**idmap.summary(), "max_vertex_deviation": deviation}
    if hasattr(idmap, "loader_mismatches"):
        loader_mismatches = idmap.loader_mismatches()
    else:
        loader_mismatches = (idmap.unmatched_lumis_triangles + idmap.unmatched_oracle_triangles
                             + idmap.unmatched_lumis_spheres + idmap.unmatched_oracle_spheres)
    checks.add("every primitive maps between lumis and the oracle (retriangulated polygons "
               "aside)", loader_mismatches == 0, json.dumps(idmap.summary()),
               severity=EXIT_WARN)

    # ids.
    lp = prim.reshape(-1).astype(np.int64)
    l_kind, l_index = idmap.to_oracle(lp)
    same = (l_kind == hits.kind) & ((l_index == hits.index) | (hits.kind < 0))
    cls = np.full(lp.shape, "match", object)
    diff_idx = np.flatnonzero(~same)
    o64 = cam.rays[:, 0:3].astype(np.float64)
    d64 = cam.rays[:, 3:6].astype(np.float64)
    if len(diff_idx):
        retri = getattr(idmap, "lumis_retriangulated", None)
        lpd = lp[diff_idx]
        l_retri = np.zeros(len(diff_idx), bool)
        if retri is not None:
            ok = (lpd >= 0) & (lpd < len(retri))
            l_retri[ok] = retri[lpd[ok]]
        matched_o = np.zeros(len(geom.triangles), bool)
        matched_o[idmap.index[idmap.kind == 1]] = True
        ok_kind, ok_index = hits.kind[diff_idx], hits.index[diff_idx]
        o_unmatched = np.zeros(len(diff_idx), bool)
        o_tri = ok_kind == 1
        o_unmatched[o_tri] = ~matched_o[ok_index[o_tri]]
        cls[diff_idx], pa, pb = classify(o64[diff_idx], d64[diff_idx], lprims.of(lpd),
                                         l_kind[diff_idx] >= 0, l_retri,
                                         Prims.of_oracle(geom, ok_kind, ok_index), o_unmatched,
                                         args.edge_tol)
    counts = {c: int(np.sum(cls == c)) for c in CLASSES}
    bad = counts["mismatch"] + counts["unmapped"]
    id_stats = {"status": STATUS[EXIT_FAIL if bad else EXIT_OK], "code": EXIT_FAIL if bad else 0,
                "oracle_hits": int((hits.kind >= 0).sum()), **counts}
    examples = {}
    for k, i in enumerate(diff_idx):
        c = cls[i]
        if len(examples.setdefault(c, [])) >= 5:
            continue
        examples[c].append({
            "pixel": [int(i % width), int(i // width)],
            "lumis_prim": int(lp[i]), "lumis_as_oracle": [int(l_kind[i]), int(l_index[i])],
            "oracle": [int(hits.kind[i]), int(hits.index[i])],
            "lumis_Z": float(z.reshape(-1)[i]), "oracle_t": float(hits.t[i]),
            "t_on_lumis_prim": float(pa.t[k]), "t_on_oracle_prim": float(pb.t[k]),
            "lumis_prim_boundary_distance": float(pa.boundary[k]),
            "oracle_prim_boundary_distance": float(pb.boundary[k]),
            "tolerance": float(max(pa.tol[k], pb.tol[k]))})
    if examples:
        id_stats["examples"] = examples

    # How far each oracle hit point may move for a ray error of --ray-eps (lateral offset
    # eps * (distance + |eye|)), divided by the cosine of incidence: the allowance of Z
    # (relative) and N (times the normal's rate of change along the surface) per pixel.
    o_hit = hits.kind >= 0
    l_hit = lp >= 0
    dlen = np.linalg.norm(d64, axis=1)
    t_hit = np.where(o_hit, hits.t, 0.0)
    cos_i = np.abs(np.einsum("ij,ij->i", d64 / dlen[:, None], hits.normal))
    p = o64 + t_hit[:, None] * d64
    # A ray moved sideways by `lateral` meets the surface `lateral / cos` further along it
    # (which turns the normal) and `lateral * tan` deeper (which changes Z); a surface point
    # off by `offset` along the normal changes both by `offset / cos`.
    lateral = args.ray_eps * (t_hit * dlen + max(1.0, float(np.abs(cam.eye).max())))
    offset = position_error(geom, hits, p)
    cos_c = np.maximum(cos_i, 1e-12)
    dp = (lateral + offset) / cos_c
    dz = (lateral * np.sqrt(np.maximum(1 - cos_i ** 2, 0)) + offset) / cos_c
    kappa = normal_rate(geom, hits)

    # Z: relative error where both saw the same surface.
    z_mask = l_hit & o_hit & ((cls == "match") | np.isin(cls, list(SAME_DEPTH)))
    z_oracle = np.where(o_hit, (p - cam.eye) @ cam.forward, np.inf)
    z_l = z.reshape(-1).astype(np.float64)
    rel = np.zeros_like(z_l)
    rel[z_mask] = (z_l[z_mask] - z_oracle[z_mask]) / z_oracle[z_mask]
    allow_z = np.where(z_mask, dz / np.where(o_hit, np.abs(z_oracle), 1.0), 0.0)
    if args.no_allowance:
        allow_z[:] = 0
    zf, zw = threshold_for("Z", fail_spec), threshold_for("Z", warn_spec)
    z_stats = channel_stats(rel[:, None], z_mask, allow_z, zf, zw, height, width, args)
    z_stats["kind"] = "relative"
    if z_mask.any():
        z_stats["max_abs_difference"] = float(np.abs(z_l[z_mask] - z_oracle[z_mask]).max())

    # N: where both hit the same primitive (or the same plane of a retriangulated polygon,
    # when flat), not normal-mapped.
    n_exp = expected_normals(geom, hits)
    mapped = np.zeros(lp.shape, bool)
    sph, tri = hits.kind == 0, hits.kind == 1
    mapped[sph] = geom.sphere_normal_mapped[hits.index[sph]]
    mapped[tri] = geom.triangle_normal_mapped[hits.index[tri]]
    flat = np.zeros(lp.shape, bool)
    flat[tri] = np.isnan(geom.vertex_normals[hits.index[tri]]).any(axis=(1, 2))
    n_base = l_hit & ((cls == "match") | ((cls == "retriangulated") & flat))
    n_mask = n_base & ~mapped
    n_l = nrm.reshape(-1, 3).astype(np.float64)
    dn = np.zeros_like(n_l)
    dn[n_mask] = n_l[n_mask] - n_exp[n_mask]
    allow_n = np.where(n_mask, dp * kappa, 0.0)
    if args.no_allowance:
        allow_n[:] = 0
    nf, nw = threshold_for("N", fail_spec), threshold_for("N", warn_spec)
    n_stats = channel_stats(dn, n_mask, allow_n, nf, nw, height, width, args)
    n_stats["kind"] = "absolute"
    nm = n_base & mapped
    n_stats["normal_mapped_excluded"] = int(nm.sum())
    if nm.any():
        # Information only: does the layer carry the normal map's perturbation?
        err = np.abs(n_l[nm] - n_exp[nm]).max(axis=1)
        n_stats["normal_mapped_matching_unperturbed"] = int(np.sum(err <= nf + (dp * kappa)[nm]))
    ki = hits.kind[n_mask]
    n_stats["compared_by_kind"] = {"triangles_smooth": int(np.sum((ki == 1) & ~flat[n_mask])),
                                   "triangles_flat": int(np.sum((ki == 1) & flat[n_mask])),
                                   "spheres": int(np.sum(ki == 0))}

    channels = {"id": id_stats, "Z": z_stats, "N": n_stats}
    if diff_path:
        code = {c: i for i, c in enumerate(CLASSES)}
        layers = {
            "Z.relerr": rel, "Z.allowance": allow_z,
            "N.X": dn[:, 0], "N.Y": dn[:, 1], "N.Z": dn[:, 2], "N.allowance": allow_n,
            "id.class": np.array([code[c] for c in cls], np.float64),
            "oracle.Z": z_oracle,
            "oracle.N.X": n_exp[:, 0], "oracle.N.Y": n_exp[:, 1], "oracle.N.Z": n_exp[:, 2],
            "oracle.kind": hits.kind.astype(np.float64),
            "oracle.index": hits.index.astype(np.float64),
        }
        write_layers(diff_path, width, height, layers)
        report["diff"] = str(diff_path)
    return finish(report, checks, channels, t_start, timings)


def finish(report, checks, channels, t_start, timings):
    report["channels"] = channels
    code = checks.code()
    for c in channels.values():
        code = max(code, c["code"])
    report["status"] = STATUS[code]
    report["code"] = code
    timings["total_s"] = time.perf_counter() - t_start
    report["timings"] = {k: round(v, 3) for k, v in timings.items()}
    return report
