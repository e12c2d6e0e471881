#!/usr/bin/env python3
"""Entry point kept for `python tools/check_passes_sum.py`; the tool is
lumis_tools/check_passes_sum.py (see its --help), also `python -m lumis_tools.check_passes_sum`.
As a script, tools/ is on sys.path, so this needs no installation."""

from lumis_tools.check_passes_sum import cli

if __name__ == "__main__":
    cli()
