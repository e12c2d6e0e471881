"""`Scene.render(display_server=...)`: the tiles, then the finished image, reach a viewer that
speaks tev's protocol (a receiver here, decoding the packets as tev's Ipc.cpp lays them out),
and the finished image is the returned one; a viewer that is absent is a RuntimeWarning, and a
bad address a ValueError, neither changing the image."""

from __future__ import annotations

import socket
import struct
import threading

import numpy as np
import pytest

import lumis
from conftest import SCENES


def receive(server, into):
    conn, _ = server.accept()
    with conn:
        chunks = []
        while b := conn.recv(1 << 20):
            chunks.append(b)
    into.append(b"".join(chunks))


def rebuild(data: bytes):
    """The images a viewer shows after `data`: {name: {channel: (H, W) array}}."""
    images, at = {}, 0
    while at < len(data):
        (n,) = struct.unpack_from("<I", data, at)
        p, at = data[at:at + n], at + n
        kind, name_end = p[4], p.index(b"\0", 6)
        name, i = p[6:name_end].decode(), name_end + 1

        def string():
            nonlocal i
            end = p.index(b"\0", i)
            s, i = p[i:end].decode(), end + 1
            return s

        if kind == 4:
            w, h, c = struct.unpack_from("<iii", p, i)
            i += 12
            images[name] = {string(): np.zeros((h, w), np.float32) for _ in range(c)}
        else:
            assert kind == 6
            (c,) = struct.unpack_from("<i", p, i)
            i += 4
            names = [string() for _ in range(c)]
            x, y, w, h = struct.unpack_from("<iiii", p, i)
            i += 16 + 16 * c  # offsets and strides: interleaved (checked by tools/check_tev_packets.py)
            tile = np.frombuffer(p, "<f4", offset=i).reshape(h, w, c)
            for k, ch in enumerate(names):
                images[name][ch][y:y + h, x:x + w] = tile[:, :, k]
    return images


def test_the_viewer_ends_on_the_returned_image(tmp_path):
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(1)
    got: list = []
    t = threading.Thread(target=receive, args=(server, got), daemon=True)
    t.start()
    scene = lumis.load(SCENES / "default.toml")
    out = tmp_path / "live.exr"
    image = scene.render(48, 32, 1, aovs=["albedo"], path=out,
                         display_server=f"127.0.0.1:{server.getsockname()[1]}")
    t.join(timeout=30)
    shown = rebuild(got[0])[str(out)]
    assert sorted(shown) == sorted(image)
    for name, plane in image.items():
        assert np.array_equal(shown[name], plane.astype(np.float32)), name
    plain = scene.render(48, 32, 1, aovs=["albedo"])
    for name in image:
        assert np.array_equal(image[name], plain[name], equal_nan=True), name


def test_no_viewer_is_a_warning_and_a_bad_address_an_error():
    scene = lumis.load(SCENES / "default.toml")
    free = socket.socket()
    free.bind(("127.0.0.1", 0))
    port = free.getsockname()[1]
    free.close()
    with pytest.warns(RuntimeWarning, match="could not connect to the display server"):
        image = scene.render(16, 8, 1, display_server=str(port))
    plain = scene.render(16, 8, 1)
    for name in image:
        assert np.array_equal(image[name], plain[name], equal_nan=True), name
    with pytest.raises(ValueError, match=r"\[HOST:\]PORT"):
        scene.render(16, 8, 1, display_server="nowhere:")
