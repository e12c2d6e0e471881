"""bench_mitsuba's image check (lumis_tools.rgb_images): the exposure scale and the relative
RMSE it fails on, on images with known answers, and the EXR round trip it reads them through."""

from __future__ import annotations

import numpy as np
import pytest

from lumis_tools.rgb_images import agreement, read_exr_rgb, write_exr_rgb


def test_same_image_at_another_exposure_agrees_after_scaling():
    lumis = np.random.default_rng(0).random((9, 16, 3))
    a = agreement(0.5 * lumis, lumis)  # Mitsuba's image half as bright
    assert a["scale"] == pytest.approx(2.0, rel=1e-12)
    assert a["rel_rmse"] == pytest.approx(0.0, abs=1e-12)
    # Unscaled, the error is that of the factor: |0.5 x - x| / rms(x) = 0.5.
    assert a["rel_rmse_unscaled"] == pytest.approx(0.5, rel=1e-12)


def test_one_wrong_pixel_by_hand():
    lumis = np.ones((2, 2, 3))
    mitsuba = lumis.copy()
    mitsuba[0, 0] = 0.0  # 3 of 12 samples dark
    a = agreement(mitsuba, lumis)
    # Least squares: scale = (m . l) / (m . m) = 9 / 9 = 1; error sqrt(3 / 12) = 0.5 of rms 1.
    assert a["scale"] == 1.0
    assert a["rel_rmse"] == pytest.approx(0.5, rel=1e-12)
    assert a["rel_rmse"] > 0.02  # bench_mitsuba's default --max-rmse fails it


def test_exr_rgb_round_trip(tmp_path):
    rgb = np.random.default_rng(1).random((5, 7, 3)).astype(np.float32)
    write_exr_rgb(tmp_path / "x.exr", rgb)
    np.testing.assert_array_equal(read_exr_rgb(tmp_path / "x.exr"), rgb)
