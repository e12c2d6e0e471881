#!/usr/bin/env python3
"""Runs the cross-checks (hits, EXR and the --aov layers) over the default scene, every asset in assets/ and the
paper's scenes (../shared/paper-scenes/scenes, or --paper-scenes DIR), as CI does.

    tools/crosscheck_all.py [--reports DIR] [--require-paper-scenes] [--lumis PATH]

Each check runs as its own process (tools/crosscheck_hits.py, tools/crosscheck_exr.py,
tools/crosscheck_aov.py), so one
scene's failure cannot disturb the next. Exit 1 if any check fails, 2 if one could not run (or
the paper scenes are required and missing); a JSON report per scene and check goes to --reports
(default target/crosscheck)."""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

from . import REPO, TOOLS, exitcodes, lumis


# Files the oracles' own glTF reader (geometry.py) cannot place: it reads node meshes, not the
# EXT_mesh_gpu_instancing extension, so it would compare lumis against a different scene.
# tests/it/gltf_instancing.rs checks that file on pixels and against its flattened render.
ORACLE_CANNOT_READ = {"gpu_instancing.gltf"}


def scenes(paper_dir: Path, require_paper: bool):
    out = [REPO / "scenes" / "default.toml"]
    assets = REPO / "assets"
    out += sorted(assets.glob("*.obj"))
    out += sorted(p for p in (assets / "gltf").glob("*.gl*")
                  if p.suffix in (".gltf", ".glb") and p.name not in ORACLE_CANNOT_READ)
    paper = sorted(paper_dir.glob("*.scn")) if paper_dir.is_dir() else []
    if not paper and require_paper:
        raise exitcodes.SetupError(f"no paper scenes in {paper_dir}")
    return out + paper


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--reports", type=Path, default=REPO / "target" / "crosscheck")
    ap.add_argument("--paper-scenes", type=Path,
                    default=REPO.parent / "shared" / "paper-scenes" / "scenes")
    ap.add_argument("--require-paper-scenes", action="store_true")
    ap.add_argument("--only", choices=("hits", "exr", "aov"), help="run just one of the checks")
    lumis.add_argument(ap)
    args = ap.parse_args(argv)
    # Checked once here rather than failing every scene the same way (and passed on as it is).
    exe = args.lumis or lumis.binary()
    args.reports.mkdir(parents=True, exist_ok=True)
    failed = []
    checks = [c for c in ("hits", "exr", "aov") if args.only in (None, c)]
    for scene in scenes(args.paper_scenes, args.require_paper_scenes):
        for check in checks:
            report = args.reports / f"{scene.stem}{scene.suffix.replace('.', '_')}.{check}.json"
            cmd = [sys.executable, str(TOOLS / f"crosscheck_{check}.py"), str(scene),
                   "--report", str(report), "--quiet", "--lumis", str(exe)]
            start = time.monotonic()
            p = subprocess.run(cmd, capture_output=True, text=True)
            took = time.monotonic() - start
            lines = (p.stdout + p.stderr).strip().splitlines()
            print(f"[{check:4}] {took:5.1f}s " + ("\n" + " " * 13).join(lines or ["(no output)"]),
                  flush=True)
            if p.returncode != 0:
                failed.append((p.returncode,
                               f"{check} {scene.relative_to(REPO.parent)} (exit {p.returncode})"))
    if failed:
        print("\nFAILED:\n  " + "\n  ".join(line for _, line in failed))
        # 2 when every failure is a check that could not run; any real failure makes it 1.
        setup_only = all(code == exitcodes.SETUP for code, _ in failed)
        return exitcodes.SETUP if setup_only else exitcodes.FAILED
    print(f"\nall cross-checks passed; reports in {args.reports}")
    return exitcodes.OK


def cli():
    exitcodes.run(main, prog="crosscheck_all")


if __name__ == "__main__":
    cli()
