"""The instruction counter's own arithmetic: reading callgrind's total and thinning a ray set
(the callgrind runs themselves are measurements, recorded in BENCHMARKS.md)."""

from __future__ import annotations

import numpy as np
import pytest

from lumis_tools import exitcodes
from lumis_tools.bench_instructions import callgrind_total, thin


def test_the_total_is_read_from_the_summary_or_totals_line(tmp_path):
    out = tmp_path / "cg.out"
    out.write_text("version: 1\ncreator: callgrind-3.19.0\nevents: Ir\nfl=(1) a.c\n"
                   "fn=(1) main\n3 10\nsummary: 1234567\ntotals: 1234567\n")
    assert callgrind_total(out) == 1234567


def test_a_file_without_a_total_is_a_setup_error(tmp_path):
    out = tmp_path / "cg.out"
    out.write_text("events: Ir\n")
    with pytest.raises(exitcodes.SetupError, match="no totals line"):
        callgrind_total(out)


def test_thinning_keeps_every_kth_ray_in_order():
    rays = np.arange(100 * 8, dtype=np.float32).reshape(100, 8)
    kept = thin(rays, 10)
    assert kept.shape == (10, 8)
    assert np.array_equal(kept[:, 0], rays[::10, 0])
    assert thin(rays, 1000).shape == (100, 8)
