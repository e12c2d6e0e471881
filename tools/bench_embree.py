#!/usr/bin/env python3
"""Entry point kept for `python tools/bench_embree.py`; the tool is
lumis_tools/bench_embree.py (see its --help), also `python -m lumis_tools.bench_embree`.
As a script, tools/ is on sys.path, so this needs no installation."""

from lumis_tools.bench_embree import cli

if __name__ == "__main__":
    cli()
