#!/usr/bin/env python3
"""Entry point kept for `python tools/bench_live_view.py`; the tool is
lumis_tools/bench_live_view.py (see its --help), also `python -m lumis_tools.bench_live_view`.
As a script, tools/ is on sys.path, so this needs no installation."""

from lumis_tools.bench_live_view import cli

if __name__ == "__main__":
    cli()
