"""The Python examples of README.md and docs/python.md run as written (from the checkout's
root, where their relative paths point) and show what they claim: their own asserts hold."""

from __future__ import annotations

import re

import pytest

from conftest import ROOT


def python_blocks(path):
    return re.findall(r"```python\n(.*?)```", path.read_text(), re.S)


@pytest.mark.parametrize("doc,index", [("README.md", 0), ("docs/python.md", 0)])
def test_example_runs_as_written(doc, index, monkeypatch):
    pytest.importorskip("embreex")
    pytest.importorskip("trimesh")
    code = python_blocks(ROOT / doc)[index]
    monkeypatch.chdir(ROOT)
    exec(compile(code, f"{doc}[python {index}]", "exec"), {})
