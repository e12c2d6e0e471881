#!/usr/bin/env python3
"""Entry point kept for `python tools/bench_trimesh.py`; the tool is
lumis_tools/bench_trimesh.py (see its --help), also `python -m lumis_tools.bench_trimesh`.
As a script, tools/ is on sys.path, so this needs no installation."""

from lumis_tools.bench_trimesh import cli

if __name__ == "__main__":
    cli()
