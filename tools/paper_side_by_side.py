#!/usr/bin/env python3
"""Entry point kept for `python tools/paper_side_by_side.py`; the tool is
lumis_tools/paper_side_by_side.py (see its --help), also `python -m lumis_tools.paper_side_by_side`.
As a script, tools/ is on sys.path, so this needs no installation."""

from lumis_tools.paper_side_by_side import cli

if __name__ == "__main__":
    cli()
