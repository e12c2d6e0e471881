"""COMPARE mode of crosscheck_exr (`--compare A B`): an idiff clone, two EXRs channel by
channel, matched by name, with idiff's rules and defaults."""

from __future__ import annotations

import numpy as np

from .exr_file import read_exr, write_layers
from .idiff import (BIG, EXIT_FILE, EXIT_OK, EXIT_SIZE, STATUS, ToolError, compare_stats,
                    threshold_for)


def compare_files(a_path, b_path, args, fail_spec, warn_spec):
    report = {"a": str(a_path), "b": str(b_path), "channels": {}}
    try:
        a, b = read_exr(a_path), read_exr(b_path)
    except ToolError as e:
        report.update(status=STATUS[EXIT_FILE], code=EXIT_FILE, error=str(e))
        return report
    names_a, names_b = list(a.spec.channelnames), list(b.spec.channelnames)
    report["size"] = [list(a.size), list(b.size)]
    report["channel_names"] = [names_a, names_b]
    if a.size != b.size or sorted(names_a) != sorted(names_b) or a.nsubimages != b.nsubimages:
        report.update(status=STATUS[EXIT_SIZE], code=EXIT_SIZE,
                      error="the images differ in size, parts or channel names")
        return report
    report["type_differences"] = {n: [a.formats[n], b.formats[n]] for n in names_a
                                  if a.formats[n] != b.formats[n]}
    w, h = a.size
    code = EXIT_OK
    diff = {}
    for n in names_a:
        x, y = a.pixels[n].copy(), b.pixels[n].copy()
        equal = (x == y) | (np.isnan(x) & np.isnan(y))
        x[equal] = 0
        y[equal] = 0
        # Unequal pairs with an inf or NaN: a huge finite difference (compare() miscounts them).
        odd = ~np.isfinite(x) | ~np.isfinite(y)
        x[odd], y[odd] = 0, BIG
        stats = compare_stats(x, y, threshold_for(n, fail_spec), threshold_for(n, warn_spec),
                              w * h, args, args.failrelative, args.warnrelative)
        stats["different_pixels"] = int((~equal).sum())
        stats["nonfinite"] = int(odd.sum())
        report["channels"][n] = stats
        code = max(code, stats["code"])
        with np.errstate(invalid="ignore"):
            diff[n] = np.where(equal, 0.0, a.pixels[n].astype(np.float64) - b.pixels[n])
    if args.diff:
        write_layers(args.diff, w, h, diff)
        report["diff"] = str(args.diff)
    report.update(status=STATUS[code], code=code)
    return report


def print_compare(r, verbose):
    print(f"{r['status'].upper():6} {r['a']} vs {r['b']}")
    if "error" in r:
        extra = (f": sizes {r['size']}, channels {r['channel_names']}" if "size" in r else "")
        print(f"    {r['error']}{extra}")
    for n, c in r["channels"].items():
        if c["code"] or verbose:
            print(f"    {n}: max {c['maxerror']:.3g} at {c['max_at']}, mean {c['meanerror']:.3g}"
                  f", {c['nwarn']} over {c['warn']}, {c['nfail']} over {c['fail']}"
                  + (f", {c['nonfinite']} with inf/NaN on one side" if c["nonfinite"] else "")
                  + f" -> {c['status']}")
