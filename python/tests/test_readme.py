"""The Python examples of README.md and docs/ run as written (from the checkout's root, where
their relative paths point) and show what they claim: their own asserts hold. A page's blocks
run in order in one namespace, as a reader types them into one session; API signatures are
fenced as `text`, not `python`. Not run: docs/cryptomatte.md's (it reads a render's file)."""

from __future__ import annotations

import re

import pytest

from conftest import ROOT

NOT_RUN = {"cryptomatte.md"}


def python_blocks(path):
    """The top-level ```python blocks of a Markdown file."""
    return re.findall(r"^```python\n(.*?)^```", path.read_text(), re.S | re.M)


PAGES = ["README.md"] + sorted(
    f"docs/{p.name}" for p in (ROOT / "docs").glob("*.md")
    if p.name not in NOT_RUN and python_blocks(p))


@pytest.mark.parametrize("page", PAGES)
def test_examples_run_as_written(page, monkeypatch):
    pytest.importorskip("embreex")
    pytest.importorskip("trimesh")
    monkeypatch.chdir(ROOT)
    namespace: dict = {}
    blocks = python_blocks(ROOT / page)
    assert blocks, page
    for i, code in enumerate(blocks):
        exec(compile(code, f"{page} [python block {i}]", "exec"), namespace)


def test_the_readme_and_python_docs_have_examples():
    assert "README.md" in PAGES and "docs/python.md" in PAGES
