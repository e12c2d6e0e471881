#!/usr/bin/env python3
"""Entry point kept for `python tools/check_tev_packets.py`; the tool is
lumis_tools/check_tev_packets.py (see its --help), also `python -m lumis_tools.check_tev_packets`.
As a script, tools/ is on sys.path, so this needs no installation."""

from lumis_tools.check_tev_packets import cli

if __name__ == "__main__":
    cli()
