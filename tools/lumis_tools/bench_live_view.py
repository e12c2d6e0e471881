#!/usr/bin/env python3
"""What a live viewer costs a render: `lumis render --display-server` into a receiver that
reads and decodes every packet as fast as it comes (tev's role), against the same render
without one, interleaved over rounds.

    tools/bench_live_view.py [SCENE] [--size 1280x720] [--spp 2] [--rounds 7] [--lumis PATH]

Each round runs both renders once, the order alternating from round to round. Reported: the
medians of the render time (`time.render_s` of --stats-json: the tracing, during which tiles
are streamed), of the write time (which with a viewer includes sending the finished image,
at most about a second) and of the process's wall time, and the ratio with/without. The
receiver is in this process, on its own thread. Exit 0 (a measurement, no target enforced)."""

from __future__ import annotations

import argparse
import json
import socket
import statistics
import subprocess
import tempfile
import threading
import time
from pathlib import Path

from . import exitcodes
from . import lumis as lumis_run
from .machine import cpu_summary
from .sizes import wxh


def parse_args(argv=None):
    p = argparse.ArgumentParser(description="The cost of --display-server with a live viewer.",
                                epilog="Method:\n" + "\n".join("  " + l for l in __doc__.splitlines()),
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scene", nargs="?", help="scene file (default: the built-in default scene)")
    p.add_argument("--size", default="1280x720", metavar="WxH", help="default 1280x720")
    p.add_argument("--spp", type=int, default=2, help="per axis; default 2")
    p.add_argument("--rounds", type=int, default=7, help="default 7")
    lumis_run.add_argument(p)
    args = p.parse_args(argv)
    args.width, args.height = wxh(p, "--size", args.size, "1280x720")
    return args


class Viewer:
    """A TCP server that reads every byte of each connection and splits it into packets."""

    def __init__(self):
        self.server = socket.socket()
        self.server.bind(("127.0.0.1", 0))
        self.server.listen(4)
        self.port = self.server.getsockname()[1]
        self.packets = 0
        threading.Thread(target=self.serve, daemon=True).start()

    def serve(self):
        buf = bytearray(1 << 24)
        view = memoryview(buf)
        while True:
            conn, _ = self.server.accept()
            with conn:
                # Each packet read whole into one buffer (its length first), no copies: the
                # receiver should cost the shared cores as little as tev's reader does.
                while True:
                    if not self.read_exactly(conn, view[:4]):
                        break
                    n = int.from_bytes(buf[:4], "little")
                    if n > len(buf):
                        buf = bytearray(n)
                        view = memoryview(buf)
                    if not self.read_exactly(conn, view[4:n]):
                        break
                    self.packets += 1

    @staticmethod
    def read_exactly(conn, into) -> bool:
        got = 0
        while got < len(into):
            k = conn.recv_into(into[got:])
            if k == 0:
                return False
            got += k
        return True


def main(argv=None):
    args = parse_args(argv)
    lumis_run.use(args.lumis)
    exe = lumis_run.binary()
    viewer = Viewer()
    times = {"without": [], "with": []}
    with tempfile.TemporaryDirectory(prefix="bench-live-") as tmp:
        for r in range(args.rounds):
            for which in (["without", "with"] if r % 2 == 0 else ["with", "without"]):
                stats = Path(tmp) / f"{which}.json"
                cmd = [str(exe), "render", *([args.scene] if args.scene else []),
                       "-q", "-o", str(Path(tmp) / f"{which}.exr"), "--width", str(args.width),
                       "--height", str(args.height), "--spp", str(args.spp),
                       "--stats-json", str(stats)]
                if which == "with":
                    cmd += ["--display-server", str(viewer.port)]
                t = time.perf_counter()
                subprocess.run(cmd, check=True)
                wall = time.perf_counter() - t
                s = json.loads(stats.read_text())["time"]
                times[which].append((s["render_s"], s["write_s"], wall))
    print(f"machine: {cpu_summary()}; {args.width}x{args.height}, {args.spp}x{args.spp} spp, "
          f"{args.scene or 'the default scene'}; {args.rounds} interleaved rounds; "
          f"{viewer.packets} packets received")
    med = {k: [statistics.median(x[i] for x in v) for i in range(3)] for k, v in times.items()}
    print("| | render s | write s | wall s |\n|---|---:|---:|---:|")
    for k in ("without", "with"):
        print(f"| {k} a viewer | " + " | ".join(f"{x:.3f}" for x in med[k]) + " |")
    print("| with / without | " + " | ".join(
        f"{a / b:.3f}" for a, b in zip(med["with"], med["without"])) + " |")
    return exitcodes.OK


def cli():
    exitcodes.run(main, setup_errors=(OSError,))


if __name__ == "__main__":
    cli()
