"""idiff's rules, as OpenImageIO's idiff applies them, for the EXR cross-check: thresholds by
channel, the pass / warn / fail verdict over ImageBufAlgo.compare's counts, the per-channel
statistics (with per-pixel allowances in scene mode), and the status levels of the reports.

The levels are idiff's exit codes and stay in the JSON reports as they were; the process exit
status maps them onto the tools' scheme (exit_status, tools/README.md)."""

from __future__ import annotations

import math

import numpy as np
import OpenImageIO as oiio

from . import exitcodes

EXIT_OK, EXIT_WARN, EXIT_FAIL, EXIT_SIZE, EXIT_FILE = 0, 1, 2, 3, 4
STATUS = {EXIT_OK: "pass", EXIT_WARN: "warn", EXIT_FAIL: "fail", EXIT_SIZE: "differ",
          EXIT_FILE: "error"}

# Scene mode defaults: Z relative error, N absolute error per component.
SCENE_FAIL = {"Z": 1e-4, "N": 1e-3}
SCENE_WARN = {"Z": 1e-5, "N": 1e-4}
# idiff's defaults.
IDIFF_FAIL = 1e-6
IDIFF_WARN = 1e-6
# Stands in for an infinite or NaN difference, which ImageBufAlgo.compare miscounts.
BIG = 1e30


class ToolError(exitcodes.SetupError):
    """A file could not be read or written, or lumis failed: level "error" (exit status 2)."""


class UsageError(exitcodes.SetupError):
    """Bad command line (exit status 2)."""


def exit_status(level):
    """The process exit status of a report level: pass 0; warn, fail and differ 1 (a check
    did not pass: idiff too exits non-zero on warnings); error 2 (nothing could be checked)."""
    if level == EXIT_OK:
        return exitcodes.OK
    return exitcodes.SETUP if level == EXIT_FILE else exitcodes.FAILED


def parse_thresholds(values, defaults, mode):
    """`VALUE` or `CHANNEL=VALUE` items over `defaults` (a dict, or a float for all channels).
    Returns (default for unnamed channels, {channel: value})."""
    base = defaults if isinstance(defaults, float) else None
    per = {} if isinstance(defaults, float) else dict(defaults)
    for item in values or []:
        name, sep, val = item.rpartition("=")
        try:
            v = float(val)
        except ValueError:
            raise UsageError(f"bad threshold {item!r}: want VALUE or CHANNEL=VALUE") from None
        if not sep:
            if mode == "scene":
                per = {k: v for k in per}
            else:
                base, per = v, {}
        else:
            if mode == "scene" and name not in SCENE_FAIL:
                raise UsageError(f"threshold channel {name!r}: scene mode knows Z and N")
            per[name] = v
    return base, per


def threshold_for(channel, spec):
    base, per = spec
    return per.get(channel, base)


def verdict(res, npels, fail, warn, failpercent, warnpercent, hardfail, hardwarn):
    """idiff's decision for one CompareResults over `npels` compared pixels."""
    if res.nfail > failpercent / 100.0 * npels or res.maxerror > hardfail:
        return EXIT_FAIL
    if res.nwarn > warnpercent / 100.0 * npels or res.maxerror > hardwarn:
        return EXIT_WARN
    return EXIT_OK


def to_buf(arr):
    """An OIIO float ImageBuf of an (H, W) or (H, W, C) array."""
    arr = np.ascontiguousarray(arr, np.float32)
    if arr.ndim == 2:
        arr = arr[:, :, None]
    h, w, c = arr.shape
    buf = oiio.ImageBuf(oiio.ImageSpec(w, h, c, oiio.FLOAT))
    buf.set_pixels(oiio.ROI(0, w, 0, h, 0, 1, 0, c), arr)
    return buf


def _check_compare(res):
    """CompareResults.error is also set when pixels fail; only a message means it broke."""
    msg = oiio.geterror()
    if res.error and msg:
        raise ToolError(f"ImageBufAlgo.compare failed: {msg}")


def compare_stats(a, b, fail, warn, npels, args, failrel=0.0, warnrel=0.0):
    """ImageBufAlgo.compare of two arrays (same shape) plus idiff's verdict."""
    res = oiio.ImageBufAlgo.compare(to_buf(a), to_buf(b), fail, warn, failrel, warnrel)
    _check_compare(res)
    npels = max(npels, 1)
    total = a.shape[0] * a.shape[1] * (a.shape[2] if a.ndim == 3 else 1)
    ncomp = npels * (a.shape[2] if a.ndim == 3 else 1)
    status = verdict(res, npels, fail, warn, args.failpercent, args.warnpercent,
                     args.hardfail, args.hardwarn)
    return {
        "status": STATUS[status], "code": status,
        "fail": fail, "warn": warn,
        "nfail": int(res.nfail), "nwarn": int(res.nwarn),
        "maxerror": float(res.maxerror),
        "max_at": [int(res.maxx), int(res.maxy)] if res.maxerror else None,
        # compare averages over every pixel; rescaled to the compared ones.
        "meanerror": float(res.meanerror) * total / max(ncomp, 1),
        "rms_error": float(res.rms_error) * math.sqrt(total / max(ncomp, 1)),
        "PSNR": float(res.PSNR),
    }


def channel_stats(diff, mask, allow, fail, warn, height, width, args):
    """idiff-style statistics of `diff` ((H*W, C) differences) over the pixels of `mask`.

    Each pixel has an allowance: the error that the float32 limits of lumis's ray and hit point
    can cause there. Where it is at most `warn` (well-conditioned pixels, nearly all), the
    pixels go through ImageBufAlgo.compare with the plain thresholds. Elsewhere (grazing
    incidence, small spheres seen from afar) the pixel is ill-conditioned: its thresholds are
    `warn + allowance` and `fail + allowance`. The counts of both sets decide, as in idiff."""
    ill = mask & (allow > warn)
    regular = mask & ~ill
    c = diff.shape[1]
    # compare() loses count on inf and NaN; they become a huge finite error (and are counted).
    nonfinite = int((~np.isfinite(diff[mask])).any(axis=1).sum())
    diff = np.nan_to_num(diff, nan=BIG, posinf=BIG, neginf=-BIG)
    d = np.where(regular[:, None], diff, 0.0).reshape(height, width, c)
    res = oiio.ImageBufAlgo.compare(to_buf(d), to_buf(np.zeros_like(d)), fail, warn)
    _check_compare(res)
    n_reg = int(regular.sum())
    scale = d.size / max(n_reg * c, 1)  # compare averages over every pixel
    err = np.abs(diff[ill]).max(axis=1) if ill.any() else np.zeros(0)
    ill_warn = err > warn + allow[ill]
    ill_fail = err > fail + allow[ill]
    nwarn = int(res.nwarn) + int(ill_warn.sum())
    nfail = int(res.nfail) + int(ill_fail.sum())
    npels = max(int(mask.sum()), 1)
    if nfail > args.failpercent / 100.0 * npels or res.maxerror > args.hardfail:
        code = EXIT_FAIL
    elif nwarn > args.warnpercent / 100.0 * npels or res.maxerror > args.hardwarn:
        code = EXIT_WARN
    else:
        code = EXIT_OK
    stats = {
        "status": STATUS[code], "code": code, "fail": fail, "warn": warn,
        "compared": n_reg, "nfail": nfail, "nwarn": nwarn,
        "maxerror": float(res.maxerror),
        "max_at": [int(res.maxx), int(res.maxy)] if res.maxerror else None,
        "meanerror": float(res.meanerror) * scale,
        "rms_error": float(res.rms_error) * math.sqrt(scale),
        "PSNR": float(res.PSNR),
        "nonfinite": nonfinite,
        "ill_conditioned": int(ill.sum()),
        "ill_conditioned_nwarn": int(ill_warn.sum()),
        "ill_conditioned_nfail": int(ill_fail.sum()),
    }
    if ill.any():
        stats["ill_conditioned_max_error"] = float(err.max())
        stats["ill_conditioned_max_allowance"] = float(allow[ill].max())
        # The worst pixel relative to its own warning threshold (<= 1: no warning).
        stats["ill_conditioned_worst_over_warn"] = float((err / (warn + allow[ill])).max())
    bad = np.flatnonzero(ill)[ill_warn][:10]
    if len(bad):
        stats["ill_conditioned_over_threshold"] = [
            {"pixel": [int(i % width), int(i // width)], "error": float(np.abs(diff[i]).max()),
             "allowance": float(allow[i])} for i in bad]
    return stats
