#!/usr/bin/env python3
"""Entry point kept for `python tools/gen_gltf_assets.py`; the tool is
lumis_tools/gen_gltf_assets.py (see its --help), also `python -m lumis_tools.gen_gltf_assets`.
As a script, tools/ is on sys.path, so this needs no installation."""

from lumis_tools.gen_gltf_assets import cli

if __name__ == "__main__":
    cli()
