#!/usr/bin/env python3
"""Runs both cross-checks (hits and EXR) over the default scene, every asset in assets/ and the
paper's scenes (../shared/paper-scenes/scenes, or --paper-scenes DIR), as CI does.

    tools/crosscheck_all.py [--reports DIR] [--require-paper-scenes]

Exit 1 if any check fails; a JSON report per scene and check goes to --reports
(default target/crosscheck)."""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

TOOLS = Path(__file__).resolve().parent
REPO = TOOLS.parent


def scenes(paper_dir: Path, require_paper: bool):
    out = [REPO / "scenes" / "default.toml"]
    assets = REPO / "assets"
    out += sorted(assets.glob("*.obj"))
    out += sorted(p for p in (assets / "gltf").glob("*.gl*") if p.suffix in (".gltf", ".glb"))
    paper = sorted(paper_dir.glob("*.scn")) if paper_dir.is_dir() else []
    if not paper and require_paper:
        sys.exit(f"crosscheck_all: no paper scenes in {paper_dir}")
    return out + paper


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--reports", type=Path, default=REPO / "target" / "crosscheck")
    ap.add_argument("--paper-scenes", type=Path,
                    default=REPO.parent / "shared" / "paper-scenes" / "scenes")
    ap.add_argument("--require-paper-scenes", action="store_true")
    ap.add_argument("--only", choices=("hits", "exr"), help="run just one of the two checks")
    args = ap.parse_args()
    args.reports.mkdir(parents=True, exist_ok=True)
    failed = []
    checks = [c for c in ("hits", "exr") if args.only in (None, c)]
    for scene in scenes(args.paper_scenes, args.require_paper_scenes):
        for check in checks:
            report = args.reports / f"{scene.stem}{scene.suffix.replace('.', '_')}.{check}.json"
            cmd = [sys.executable, str(TOOLS / f"crosscheck_{check}.py"), str(scene),
                   "--report", str(report), "--quiet"]
            start = time.monotonic()
            p = subprocess.run(cmd, capture_output=True, text=True)
            took = time.monotonic() - start
            lines = (p.stdout + p.stderr).strip().splitlines()
            print(f"[{check:4}] {took:5.1f}s " + ("\n" + " " * 13).join(lines or ["(no output)"]),
                  flush=True)
            if p.returncode != 0:
                failed.append(f"{check} {scene.relative_to(REPO.parent)} (exit {p.returncode})")
    if failed:
        print("\nFAILED:\n  " + "\n  ".join(failed))
        return 1
    print(f"\nall cross-checks passed; reports in {args.reports}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
