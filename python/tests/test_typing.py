"""The types are one source of truth: the stubs of the compiled module match its Rust
signatures (`mypy.stubtest`), the package's calls into it and a typed example of the public
API pass `mypy --strict` against them, and the `Literal` option names are the names the
library takes. The mypy checks skip only when mypy is not installed (the `[test]` extra
installs it, as CI does)."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path
from typing import get_args

import numpy as np
import pytest

import lumis
from lumis import _lumis, _types

from conftest import ASSETS, ROOT

TESTS = Path(__file__).resolve().parent
ALLOWLIST = TESTS / "stubtest_allowlist.txt"
EXAMPLE = ROOT / "python" / "examples" / "typed_usage.py"

needs_mypy = pytest.mark.skipif(
    importlib.util.find_spec("mypy") is None,
    reason="mypy is not installed (pip install './python[test]')",
)


def run_module(cwd: Path, *args: object) -> subprocess.CompletedProcess[str]:
    """`python -m ARGS` in `cwd`, a temporary directory: outside the checkout's python/ (so
    that `lumis` is the installed package, with its compiled module, not the source folder),
    and where mypy's cache goes."""
    return subprocess.run(
        [sys.executable, "-m", *map(str, args)],
        capture_output=True,
        text=True,
        cwd=cwd,
    )


@needs_mypy
def test_stubs_match_the_compiled_module(tmp_path: Path) -> None:
    p = run_module(tmp_path, "mypy.stubtest", "lumis._lumis", "--allowlist", ALLOWLIST)
    assert p.returncode == 0, p.stdout + p.stderr


@needs_mypy
def test_package_passes_mypy_strict(tmp_path: Path) -> None:
    # The package's own modules, whose calls into `_lumis` are checked against the stubs.
    p = run_module(tmp_path, "mypy", "--strict", "-p", "lumis")
    assert p.returncode == 0, p.stdout + p.stderr


@needs_mypy
def test_typed_example_passes_mypy_strict(tmp_path: Path) -> None:
    # A user's code, against the installed package.
    p = run_module(tmp_path, "mypy", "--strict", EXAMPLE)
    assert p.returncode == 0, p.stdout + p.stderr


def test_typed_example_runs() -> None:
    p = subprocess.run([sys.executable, str(EXAMPLE)], capture_output=True, text=True)
    assert p.returncode == 0, p.stdout + p.stderr
    assert "typed usage: ok" in p.stdout


def test_literal_names_are_the_names_the_library_takes() -> None:
    literals = {
        "accel": _types.Accel,
        "precision": _types.Precision,
        "up": _types.Up,
        "layout": _types.Layout,
        "tonemap": _types.Tonemap,
        "display": _types.Display,
        "aov": _types.Aov,
    }
    assert sorted(_lumis.CHOICES) == sorted(literals)
    for key, literal in literals.items():
        assert sorted(get_args(literal)) == sorted(_lumis.CHOICES[key]), key
    assert lumis.ACCELS == get_args(lumis.Accel) and lumis.ACCELS[0] == "sah"
    assert lumis.PRECISIONS == get_args(lumis.Precision)


def test_every_literal_name_is_accepted_and_others_refused() -> None:
    scene = lumis.load(ASSETS / "knot.obj")
    # Down onto the centroid of the first triangle, from above the knot.
    target = scene.triangles()[0, 1:].reshape(3, 3).mean(axis=0)
    o = (target + [0.0, 0.0, 50.0]).astype(np.float32)[None]
    d = np.array([[0.0, 0.0, -1.0]], np.float32)
    for accel in get_args(lumis.Accel):
        for precision in get_args(lumis.Precision):
            assert scene.intersect(o, d, accel=accel, precision=precision).kind[0] == 1
    for up in get_args(lumis.Up):
        lumis.load(ASSETS / "knot.obj", up=up)
    small = {"width": 4, "height": 3, "spp": 1}
    for layout in get_args(lumis.Layout):
        for tonemap in get_args(lumis.Tonemap):
            for display in get_args(lumis.Display):
                scene.render(**small, layout=layout, tonemap=tonemap, display=display)
    scene.render(**small, aovs=get_args(lumis.Aov))
    with pytest.raises(ValueError, match=r'^accel="SAH": expected "sah", "brute", "bsp" or '):
        scene.intersect(o, d, accel="SAH")  # type: ignore[arg-type]
    one_of = r'^tonemap="aces": expected one of \["none", "filmic"\]$'
    with pytest.raises(ValueError, match=one_of):
        scene.render(**small, tonemap="aces")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r'^aovs: "depth" is not a layer; expected "albedo", '):
        scene.render(**small, aovs=["depth"])  # type: ignore[list-item]
    with pytest.raises(ValueError, match=r'^up="x": expected "y" or "z"$'):
        lumis.load(ASSETS / "knot.obj", up="x")  # type: ignore[arg-type]


def test_options_cross_into_rust_by_keyword_only() -> None:
    inner = lumis.load(ASSETS / "knot.obj")._s
    o = np.zeros((1, 3), np.float32)
    d = np.array([[0.0, 0.0, -1.0]], np.float32)
    with pytest.raises(TypeError):
        inner.render(4, 3, 1)  # type: ignore[misc]
    with pytest.raises(TypeError):
        inner.intersect(o, d, 0.0, 1.0, None, "sah")  # type: ignore[misc]
    with pytest.raises(TypeError):
        _lumis.load(str(ASSETS / "knot.obj"), [])  # type: ignore[misc]
