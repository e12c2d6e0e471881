#!/usr/bin/env python3
"""Entry point kept for `python tools/bench_instructions.py`; the tool is
lumis_tools/bench_instructions.py (see its --help), also `python -m lumis_tools.bench_instructions`.
As a script, tools/ is on sys.path, so this needs no installation."""

from lumis_tools.bench_instructions import cli

if __name__ == "__main__":
    cli()
