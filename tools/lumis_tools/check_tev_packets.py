#!/usr/bin/env python3
"""Checks `lumis render --display-server` against tev's own client library: a receiver here
takes every packet lumis sends, decodes it, encodes the same fields again with `tevclient`
(`tevclient.packet.create_image` / `update_image`, Thomas Müller's reference encoder of tev's
protocol) and requires the same bytes; then it rebuilds the image as tev would and requires
the finished image to equal the EXR lumis wrote, every channel, read with OpenImageIO.

    tools/check_tev_packets.py [--size 96x64] [--spp 2] [--keep DIR] [--lumis PATH]

The render is lumis's built-in default scene with `--aov albedo,lightpaths` (so the finished
image has more channels than the streamed RGBA and the image is made again with them). Exit 0
when every packet and pixel agrees, 1 when one does not, 2 when the check could not run."""

from __future__ import annotations

import argparse
import socket
import struct
import tempfile
import threading
from pathlib import Path

import numpy as np

from . import exitcodes
from . import lumis as lumis_run
from .sizes import wxh


def parse_args(argv=None):
    p = argparse.ArgumentParser(
        description="lumis's tev packets against tevclient's, and the viewer's image against the EXR.",
        epilog="Method:\n" + "\n".join("  " + line for line in __doc__.splitlines()),
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--size", default="96x64", metavar="WxH", help="render size; default 96x64")
    p.add_argument("--spp", type=int, default=2, help="samples per pixel PER AXIS; default 2")
    p.add_argument("--keep", type=Path, metavar="DIR", help="write the render here")
    lumis_run.add_argument(p)
    args = p.parse_args(argv)
    args.width, args.height = wxh(p, "--size", args.size, "96x64")
    return args


def split_packets(data: bytes):
    """The packets of a stream: each starts with its own length (u32, counting itself)."""
    at, out = 0, []
    while at < len(data):
        (n,) = struct.unpack_from("<I", data, at)
        if n < 6 or at + n > len(data):
            raise ValueError(f"packet of {n} bytes at offset {at} of {len(data)}")
        out.append(data[at:at + n])
        at += n
    return out


class Reader:
    def __init__(self, b: bytes):
        self.b, self.at = b, 4

    def take(self, fmt):
        v = struct.unpack_from(fmt, self.b, self.at)
        self.at += struct.calcsize(fmt)
        return v if len(v) > 1 else v[0]

    def string(self):
        end = self.b.index(b"\0", self.at)
        s = self.b[self.at:end].decode()
        self.at = end + 1
        return s


def check(packets, tevclient_packet):
    """Re-encodes each packet with tevclient; returns the images rebuilt and the mismatches."""
    images, bad = {}, []
    for i, p in enumerate(packets):
        r = Reader(p)
        kind, grab = r.take("<b"), bool(r.take("<b"))
        name = r.string()
        if kind == 4:
            w, h, n = r.take("<i"), r.take("<i"), r.take("<i")
            names = [r.string() for _ in range(n)]
            again = tevclient_packet.create_image(name, w, h, names, grab)
            images[name] = {"size": (w, h), "channels": {c: np.zeros((h, w), np.float32) for c in names}}
        elif kind == 6:
            n = r.take("<i")
            names = [r.string() for _ in range(n)]
            x, y, w, h = (r.take("<i") for _ in range(4))
            offsets = [r.take("<q") for _ in range(n)]
            strides = [r.take("<q") for _ in range(n)]
            if offsets != list(range(n)) or strides != [n] * n:
                bad.append(f"packet {i}: offsets {offsets} strides {strides}, not interleaved")
                continue
            tile = np.frombuffer(p, "<f4", offset=r.at).reshape(h, w, n)
            again = tevclient_packet.update_image(name, tile, names, x, y, grab)
            for c, cname in enumerate(names):
                images[name]["channels"][cname][y:y + h, x:x + w] = tile[:, :, c]
        else:
            bad.append(f"packet {i}: type {kind}, not CreateImage (4) or UpdateImageV3 (6)")
            continue
        if bytes(again) != p:
            bad.append(f"packet {i} (type {kind}, image {name!r}): {len(p)} bytes differ from "
                       f"tevclient's {len(again)}")
    return images, bad


def receive(server: socket.socket, into: list):
    conn, _ = server.accept()
    with conn:
        chunks = []
        while True:
            b = conn.recv(1 << 20)
            if not b:
                break
            chunks.append(b)
    into.append(b"".join(chunks))


def main(argv=None):
    args = parse_args(argv)
    lumis_run.use(args.lumis)
    from tevclient import packet as tevclient_packet
    import OpenImageIO as oiio

    with tempfile.TemporaryDirectory(prefix="check-tev-") as tmp:
        folder = (args.keep or Path(tmp)).resolve()
        folder.mkdir(parents=True, exist_ok=True)
        server = socket.socket()
        server.bind(("127.0.0.1", 0))
        server.listen(1)
        got: list = []
        t = threading.Thread(target=receive, args=(server, got), daemon=True)
        t.start()
        exr = folder / "live.exr"
        lumis_run.run(["render", "-o", exr, "--width", args.width, "--height", args.height,
                       "--spp", args.spp, "--aov", "albedo,lightpaths",
                       "--display-server", server.getsockname()[1]], "the render")
        t.join(timeout=30)
        if not got:
            print("error: the receiver got no connection")
            return exitcodes.FAILED
        packets = split_packets(got[0])
        images, bad = check(packets, tevclient_packet)
        image = images.get(str(exr))
        if image is None:
            bad.append(f"no image named {str(exr)!r} (got {sorted(images)})")
        else:
            inp = oiio.ImageInput.open(str(exr))
            spec = inp.spec()
            pixels = inp.read_image(oiio.FLOAT)
            inp.close()
            for c, cname in enumerate(spec.channelnames):
                seen = image["channels"].get(cname)
                if seen is None:
                    bad.append(f"channel {cname} of the EXR never reached the viewer")
                elif not np.array_equal(seen.view(np.uint32), np.ascontiguousarray(pixels[:, :, c]).view(np.uint32)):
                    bad.append(f"channel {cname}: the viewer's pixels differ from the EXR's")
        kinds = [struct.unpack_from("<b", p, 4)[0] for p in packets]
        print(f"{len(packets)} packets ({kinds.count(4)} CreateImage, {kinds.count(6)} "
              f"UpdateImageV3), every one byte-identical to tevclient's: {not any('bytes differ' in b for b in bad)}")
        for b in bad:
            print(f"FAIL: {b}")
        if not bad:
            print(f"the viewer's image equals {exr.name} (read by OpenImageIO) in all "
                  f"{len(image['channels'])} channels")
        return exitcodes.FAILED if bad else exitcodes.OK


def cli():
    exitcodes.run(main, setup_errors=(OSError,))


if __name__ == "__main__":
    cli()
