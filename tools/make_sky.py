#!/usr/bin/env python3
"""Entry point kept for `python tools/make_sky.py`; the tool is lumis_tools/make_sky.py (see
its --help), also `python -m lumis_tools.make_sky`. As a script, tools/ is on sys.path, so
this needs no installation."""

from lumis_tools.make_sky import cli

if __name__ == "__main__":
    cli()
