#!/usr/bin/env python3
"""Entry point kept for `python tools/crosscheck_hits.py`; the tool is
lumis_tools/crosscheck_hits.py (see its --help), also `python -m lumis_tools.crosscheck_hits`.
As a script, tools/ is on sys.path, so this needs no installation."""

from lumis_tools.crosscheck_hits import cli

if __name__ == "__main__":
    cli()
