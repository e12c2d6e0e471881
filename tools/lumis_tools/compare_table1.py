#!/usr/bin/env python3
"""Puts lumis's measured Table I (the CSV of `lumis-lab paper --csv FILE`) beside the
percentages the paper reports, as a Markdown table. Standard library only.

Usage: python3 tools/compare_table1.py table1.csv
"""
import csv
import sys

from . import exitcodes

# The paper's Table I: % change of user CPU time against its baseline (RayTracing + BSP), per
# figure, for Segment_s2, Segment_s4096, Median, Segment_Median_s2, Segment_Median_s4096.
PAPER = {
    "allMaterials.scn": (-6.33, -32.39, 0.37, -13.27, -27.67),
    "ballsInAPit.scn": (-34.21, -33.19, 187.23, 47.35, 142.79),
    "ballsOnAPlane.scn": (-30.12, -31.19, -36.01, -48.09, -33.78),
    "ballsOnAPlaneClose.scn": (-33.52, -39.4, -56.88, -64.36, -43.01),
    "line.scn": (6.79, -37.15, -2.26, 9.67, -38.16),
    "lineFar.scn": (5.0, -42.08, -0.81, 4.23, -43.02),
    "modelTest2.scn": (5.65, -42.03, -0.05, 8.27, -42.33),
    "texturesInYoFace.scn": (-25.98, -34.35, 117.64, 42.13, 37.4),
    "triangleSpheres.scn": (8.82, -28.15, 2.18, 9.38, -29.23),
    "triangleTest1.scn": (-1.5, -39.29, -2.69, -4.95, -39.82),
    "tumbledStones.scn": (-30.92, -41.67, -29.87, -67.91, -52.33),
}
PAPER_TOTAL = (-31.38, -34.51, 56.96, -11.05, 33.43)
COLUMNS = ["bsp+seg2", "bsp+seg4096", "bsmp", "bsmp+seg2", "bsmp+seg4096"]
BASELINE = "bsp (baseline)"


def main(path):
    seconds = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            seconds[(row["scene"], row["config"])] = float(row["median_seconds"])
    scenes = [s for s in PAPER if (s, BASELINE) in seconds]
    header = "| figure | " + " | ".join(f"{c} paper | {c} lumis" for c in COLUMNS) + " |"
    print(header)
    print("|---|" + "---:|---:|" * len(COLUMNS))
    totals = {c: 0.0 for c in COLUMNS + [BASELINE]}
    for s in scenes:
        base = seconds[(s, BASELINE)]
        totals[BASELINE] += base
        cells = []
        for i, c in enumerate(COLUMNS):
            t = seconds.get((s, c))
            totals[c] += t or 0.0
            ours = f"{100.0 * (t / base - 1.0):+.1f}" if t else "n/a"
            cells.append(f"{PAPER[s][i]:+.1f} | {ours}")
        print(f"| {s} | " + " | ".join(cells) + " |")
    cells = []
    for i, c in enumerate(COLUMNS):
        cells.append(f"{PAPER_TOTAL[i]:+.1f} | {100.0 * (totals[c] / totals[BASELINE] - 1.0):+.1f}")
    print("| **total** | " + " | ".join(cells) + " |")


def cli(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 1:
        print(__doc__, file=sys.stderr)
        sys.exit(exitcodes.SETUP)
    exitcodes.run(lambda _: main(argv[0]), setup_errors=(OSError, KeyError))


if __name__ == "__main__":
    cli()
