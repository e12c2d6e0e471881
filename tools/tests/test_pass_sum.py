"""check_passes_sum's logic (lumis_tools.pass_sum) on synthetic layers: a set that adds up
passes in both layouts (also as an EXR read back through OpenImageIO), one perturbed pixel
fails at its place, float32 rounding passes and a HALF beauty gets its own allowance."""

from __future__ import annotations

import numpy as np
import pytest

from lumis_tools import pass_sum as ps
from lumis_tools.check_passes_sum import check_file

from conftest import write_exr

H, W = 5, 7


def layers(layout="lumis", seed=0):
    """{channel: (H, W) float32} with passes that add up to the beauty (in float64, then each
    rounded to float32 as lumis's layers are) and two lights that add up to diffuse + specular."""
    rng = np.random.default_rng(seed)
    passes = {p: rng.random((H, W, 3)) * rng.choice([0.0, 0.1, 2.0]) for p in ps.PASSES}
    key = rng.random((H, W, 3))
    fill = rng.random((H, W, 3)) * 0.3
    spec_share = rng.random((H, W, 3))
    passes["diffuse"] = (key + fill) * (1 - spec_share)
    passes["specular"] = (key + fill) * spec_share
    beauty = sum(passes.values())
    pre = ps.LAYOUTS[layout]
    ch = {}
    for i, c in enumerate(ps.RGB):
        ch[pre["beauty"] + c] = beauty[..., i]
        for p, v in passes.items():
            name = p if layout == "lumis" else ps.BLENDER_PASSES[p]
            ch[f"{pre['pass']}{name}.{c}"] = v[..., i]
        ch[f"{pre['light']}key.{c}"] = key[..., i]
        ch[f"{pre['light']}fill.{c}"] = fill[..., i]
    ch[pre["beauty"] + "A"] = np.ones((H, W))
    ch["shadow.R"] = np.ones((H, W))  # not a radiance pass: must not be summed
    return {n: np.asarray(v, np.float32) for n, v in ch.items()}


@pytest.mark.parametrize("layout", ["lumis", "blender"])
def test_a_correct_set_passes(layout):
    ch = layers(layout)
    found, passes, lights, (rel, abs_tol) = ps.check_channels(ch, {n: "float" for n in ch}, 16)
    assert found.layout == layout
    assert set(found.passes) == set(ps.PASSES) and set(found.lights) == {"key", "fill"}
    assert passes.ok and lights.ok, (passes, lights)
    assert passes.pixels == H * W and passes.bad == 0
    assert 0 < passes.max_rel < 1e-6  # float32 rounding of the layers only
    assert (rel, abs_tol) == (1e-5, 1e-6)


@pytest.mark.parametrize("layout", ["lumis", "blender"])
def test_one_perturbed_pixel_fails_at_its_place(layout):
    ch = layers(layout, seed=1)
    name = "reflection.G" if layout == "lumis" else "ViewLayer.GlossInd.G"
    ch[name][3, 2] += 1e-3 * max(1.0, float(ch[name][3, 2]))
    _, passes, lights, _ = ps.check_channels(ch, {n: "float" for n in ch}, 16)
    assert not passes.ok and passes.bad == 1 and passes.worst == (2, 3)
    assert "channel G" in passes.worst_detail
    assert lights.ok  # reflection is not direct light
    light = "light.key.B" if layout == "lumis" else "ViewLayer.Combined_key.B"
    ch[light][0, 6] *= 1.01
    _, _, lights, _ = ps.check_channels(ch, {n: "float" for n in ch}, 16)
    assert not lights.ok and lights.worst == (6, 0)


def test_nan_fails_and_zeros_pass():
    ch = {n: np.zeros((H, W), np.float32) for n in layers()}
    _, passes, lights, _ = ps.check_channels(ch, {}, 4)
    assert passes.ok and lights.ok and passes.max_abs == 0.0
    ch["emission.R"][1, 1] = np.nan
    _, passes, _, _ = ps.check_channels(ch, {}, 4)
    assert not passes.ok and passes.nonfinite == 1


def test_tolerance_by_hand():
    assert ps.tolerance(16) == (1e-5, 1e-6)  # 2 (16 + 32) 2^-24 = 5.7e-6 < 1e-5
    assert ps.tolerance(1024)[0] == pytest.approx(2 * 1056 * 2.0 ** -24)
    assert ps.tolerance(16, half_beauty=True)[0] == pytest.approx(1e-5 + 2.0 ** -11)


def test_check_sum_by_hand():
    total = np.array([[[1.0, 0.0, 10.0]]])
    parts = [np.array([[[0.5, 0.0, 4.0]]]), np.array([[[0.5, 0.0, 6.0001]]])]
    c = ps.check_sum(parts, total, 1e-5, 1e-6)
    # B: difference 1e-4 against an allowance of 1e-5 x 10.0001 + 1e-6 = 1.01e-4: inside.
    assert c.ok and c.max_abs == pytest.approx(1e-4)
    assert c.max_rel == pytest.approx(1e-4 / 10.0001)
    c = ps.check_sum(parts, total, 5e-6, 1e-6)
    assert not c.ok and c.bad == 1 and "channel B" in c.worst_detail


def test_half_beauty_needs_its_allowance():
    ch = layers()
    half = {n: (v.astype(np.float16).astype(np.float32) if n in ("R", "G", "B") else v)
            for n, v in ch.items()}
    float_formats = {n: "float" for n in half}
    half_formats = dict(float_formats, R="half", G="half", B="half")
    _, passes, _, _ = ps.check_channels(half, float_formats, 16)
    assert not passes.ok  # rounded to half, the beauty is off by up to 2^-11
    _, passes, _, (rel, _) = ps.check_channels(half, half_formats, 16)
    assert passes.ok and rel == pytest.approx(1e-5 + 2.0 ** -11)


def test_missing_layers_are_named():
    ch = layers()
    del ch["refraction.B"]
    with pytest.raises(ps.LayerError, match="refraction"):
        ps.find_layers(ch)
    with pytest.raises(ps.LayerError, match="no beauty"):
        ps.find_layers(["diffuse.R"])


def test_an_exr_read_through_openimageio(tmp_path, capsys):
    for layout in ("lumis", "blender"):
        path = write_exr(tmp_path / f"{layout}.exr", layers(layout))
        assert check_file(path)
        assert f"{layout} layout" in capsys.readouterr().out
    bad = layers()
    bad["ambient.R"][4, 6] += 0.01
    assert not check_file(write_exr(tmp_path / "bad.exr", bad))
    assert "worst pixel (x 6, y 4)" in capsys.readouterr().out
