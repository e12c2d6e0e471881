"""The lumis cross-check and benchmark tools: an independent scene loader, an Embree + float64
oracle, seeded ray sets, id mapping by position, runners for `lumis hits` / `lumis render`, and
one module per tool (`python -m lumis_tools.crosscheck_hits`, ...; see tools/README.md).

The package belongs to its checkout: it finds the lumis binary, the assets and the paper's
scenes relative to this folder, so install it editable (`pip install -e tools/`) or run the
scripts in tools/. Importing it loads nothing heavy (no numpy), so that tools can set up their
environment first and report a missing dependency themselves."""

from pathlib import Path

# tools/ and the repository root, for the binary, assets/, scenes/ and ../shared.
TOOLS = Path(__file__).resolve().parents[1]
REPO = TOOLS.parent
