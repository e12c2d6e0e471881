#!/usr/bin/env python3
"""Entry point kept for `python tools/compare_table1.py`; the tool is
lumis_tools/compare_table1.py (see its --help), also `python -m lumis_tools.compare_table1`.
As a script, tools/ is on sys.path, so this needs no installation."""

from lumis_tools.compare_table1 import cli

if __name__ == "__main__":
    cli()
