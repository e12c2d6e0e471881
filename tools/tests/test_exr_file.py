"""The EXR reader's layout checks (lumis_tools.exr_file): a file written exactly to lumis's
contract passes, and one wrongly-typed or missing channel is reported by name."""

from __future__ import annotations

from conftest import contract_channels, contract_formats, write_exr
from lumis_tools.exr_file import Checks, check_header, check_layout, read_exr


def layout_failures(path, float_rgba=False, size=(4, 3)):
    checks = Checks()
    complete = check_layout(read_exr(path), *size, float_rgba, checks)
    return complete, {c["check"]: c["detail"] for c in checks.items if not c["ok"]}, checks


def test_contract_file_passes_every_layout_check(exr_path):
    path = write_exr(exr_path("ok.exr"), contract_channels(), contract_formats())
    complete, failed, checks = layout_failures(path)
    assert complete
    assert failed == {}
    assert len(checks.items) == 5 + 10  # part, scanlines, ZIP, window, names + one per channel
    assert checks.code() == 0


def test_half_depth_channel_is_rejected(exr_path):
    formats = contract_formats()
    formats["Z"] = "half"  # depth must be FLOAT: half would round it to 11 bits
    path = write_exr(exr_path("half_z.exr"), contract_channels(), formats)
    _, failed, checks = layout_failures(path)
    assert failed == {"Z type": "half, want float"}
    assert checks.code() == 2  # the "fail" level


def test_float_rgba_without_float_flag_is_rejected(exr_path):
    path = write_exr(exr_path("float_rgba.exr"), contract_channels(),
                     contract_formats(float_rgba=True))
    _, failed, _ = layout_failures(path, float_rgba=False)
    assert set(failed) == {"R type", "G type", "B type", "A type"}
    # ... and the same file is right for a --float render.
    assert layout_failures(path, float_rgba=True)[1] == {}


def test_missing_channel_and_wrong_size(exr_path):
    px = contract_channels()
    del px["id.object"]
    path = write_exr(exr_path("no_object.exr"), px, contract_formats())
    complete, failed, _ = layout_failures(path, size=(5, 3))
    assert not complete
    assert set(failed) == {"channel names", "data window = display window = requested size"}


def test_header_without_matrices_fails(exr_path):
    path = write_exr(exr_path("bare.exr"), contract_channels(), contract_formats())
    checks = Checks()
    w2c, w2ndc = check_header(read_exr(path).spec, 1, checks)
    assert w2c is None and w2ndc is None
    failed = {c["check"] for c in checks.items if not c["ok"]}
    assert {"worldToCamera attribute", "worldToNDC attribute", "software = lumis <version>",
            "lumis/spp (int, spp^2)"} <= failed
