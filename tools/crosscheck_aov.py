#!/usr/bin/env python3
"""Entry point kept for `python tools/crosscheck_aov.py`; the tool is
lumis_tools/crosscheck_aov.py (see its --help), also `python -m lumis_tools.crosscheck_aov`.
As a script, tools/ is on sys.path, so this needs no installation."""

from lumis_tools.crosscheck_aov import cli

if __name__ == "__main__":
    cli()
