"""The idiff clone (`crosscheck_exr.py --compare A B`): identical images pass, a known
difference is found where it is and as large as it is, and the verdicts and exit statuses
follow idiff's rules mapped onto the tools' scheme."""

from __future__ import annotations

import json

import numpy as np
import pytest

from conftest import write_exr
from lumis_tools import crosscheck_exr
from lumis_tools.idiff import UsageError, exit_status, parse_thresholds


def image(seed=0, h=6, w=8):
    rng = np.random.default_rng(seed)
    return {"R": rng.random((h, w)), "Z": 1 + 10 * rng.random((h, w))}


def compare(a, b, tmp_path, *extra):
    """(exit status, the one compare result of the JSON report)."""
    report = tmp_path / "report.json"
    code = crosscheck_exr.main(["--compare", str(a), str(b), "--report", str(report),
                                "--quiet", *extra])
    return code, json.loads(report.read_text())["results"][0]


def test_identical_images_pass(tmp_path):
    px = image()
    px["Z"][0, 0] = np.inf  # equal infinities match too
    a = write_exr(tmp_path / "a.exr", px)
    b = write_exr(tmp_path / "b.exr", px)
    code, r = compare(a, b, tmp_path)
    assert code == 0
    assert r["status"] == "pass"
    for c in r["channels"].values():
        assert (c["nfail"], c["nwarn"], c["different_pixels"], c["maxerror"]) == (0, 0, 0, 0.0)


def test_one_changed_pixel_fails_at_its_place(tmp_path):
    px = image()
    a = write_exr(tmp_path / "a.exr", px)
    px["Z"][2, 5] += 1e-3  # x = 5, y = 2
    b = write_exr(tmp_path / "b.exr", px)
    code, r = compare(a, b, tmp_path)
    assert code == 1
    assert r["status"] == "fail"
    z = r["channels"]["Z"]
    assert (z["nfail"], z["different_pixels"], z["max_at"]) == (1, 1, [5, 2])
    assert z["maxerror"] == pytest.approx(1e-3, rel=1e-3)  # float32 storage of Z ~ 10
    assert r["channels"]["R"]["status"] == "pass"


def test_difference_between_warn_and_fail_thresholds_warns(tmp_path):
    px = image()
    a = write_exr(tmp_path / "a.exr", px)
    px["R"][0, 0] += 1e-3
    b = write_exr(tmp_path / "b.exr", px)
    code, r = compare(a, b, tmp_path, "--fail", "1e-2", "--warn", "1e-4")
    assert r["status"] == "warn" and r["code"] == 1  # idiff's level, kept in the report
    assert code == 1  # a warning is not a pass
    # Allowed by --warnpercent (1 pixel of 48 is 2.1 %): a pass.
    code, r = compare(a, b, tmp_path, "--fail", "1e-2", "--warn", "1e-4", "--warnpercent", "5")
    assert (code, r["status"]) == (0, "pass")


def test_infinity_against_a_number_fails(tmp_path):
    px = image()
    a = write_exr(tmp_path / "a.exr", px)
    px["Z"][1, 1] = np.inf
    b = write_exr(tmp_path / "b.exr", px)
    code, r = compare(a, b, tmp_path, "--fail", "1e9")  # any finite threshold
    assert code == 1
    assert r["channels"]["Z"]["nonfinite"] == 1
    assert r["channels"]["Z"]["nfail"] == 1


def test_different_channels_differ_and_unreadable_files_are_errors(tmp_path):
    a = write_exr(tmp_path / "a.exr", image())
    b = write_exr(tmp_path / "b.exr", {"R": image()["R"]})
    code, r = compare(a, b, tmp_path)
    assert (code, r["status"], r["code"]) == (1, "differ", 3)
    code, r = compare(a, tmp_path / "missing.exr", tmp_path)
    assert (code, r["status"], r["code"]) == (2, "error", 4)


def test_exit_status_of_each_level():
    # pass, warn, fail, differ, error
    assert [exit_status(level) for level in range(5)] == [0, 1, 1, 1, 2]


def test_thresholds_by_channel_and_for_all():
    assert parse_thresholds(["Z=1e-3"], {"Z": 1e-4, "N": 1e-3}, "scene") == \
        (None, {"Z": 1e-3, "N": 1e-3})
    assert parse_thresholds(["5e-2"], {"Z": 1e-4, "N": 1e-3}, "scene") == \
        (None, {"Z": 5e-2, "N": 5e-2})
    assert parse_thresholds(["2e-6", "R=1"], 1e-6, "compare") == (2e-6, {"R": 1.0})
    with pytest.raises(UsageError):
        parse_thresholds(["Z=lots"], 1e-6, "compare")
    with pytest.raises(UsageError):
        parse_thresholds(["Q=1"], {"Z": 1e-4, "N": 1e-3}, "scene")
