"""bench_embree_packets without timing: the 4x2 tiling of a pixel grid (ragged edges included),
the native loops' struct layout against rtcore_ray.h, the hit comparison, and both Embree loops
on a scene whose hits are known."""

from __future__ import annotations

import numpy as np
import pytest

from lumis_tools import embree_native
from lumis_tools.bench_embree import agreement
from lumis_tools.bench_embree_packets import (
    as_embreex,
    from_tile_order,
    packet_groups,
    rotated,
    same_hits,
    same_rows,
    tile_order,
)
from lumis_tools.embree_native import HEADER_LAYOUT, RECORD, packet_lanes


def test_a_4x2_grid_is_one_full_packet_row_by_row():
    assert packet_lanes(4, 2).tolist() == [[0, 1, 2, 3, 4, 5, 6, 7]]


def test_ragged_edges_give_partly_filled_packets():
    # 5 x 3: tiles of columns 0-3 and 4, rows 0-1 and 2.
    assert packet_lanes(5, 3).tolist() == [
        [0, 1, 2, 3, 5, 6, 7, 8],
        [4, -1, -1, -1, 9, -1, -1, -1],
        [10, 11, 12, 13, -1, -1, -1, -1],
        [14, -1, -1, -1, -1, -1, -1, -1],
    ]


@pytest.mark.parametrize("w,h", [(1, 1), (3, 1), (4, 2), (7, 5), (8, 6), (513, 385)])
def test_every_pixel_is_in_one_lane_of_a_4x2_tile(w, h):
    lanes = packet_lanes(w, h)
    assert lanes.dtype == np.int32 and lanes.shape == (-(-w // 4) * -(-h // 2), 8)
    used = lanes[lanes >= 0]
    assert sorted(used.tolist()) == list(range(w * h))
    assert (lanes[:, 0] >= 0).all()  # the native loop fills empty lanes from lane 0
    for packet in lanes:
        ys, xs = np.divmod(packet[packet >= 0], w)
        assert xs.max() - xs.min() < 4 and ys.max() - ys.min() < 2
        assert xs.min() % 4 == 0 and ys.min() % 2 == 0


def test_tile_order_of_whole_tiles_is_the_packets_order():
    # 8 x 4: tiles (columns 0-3, 4-7) x (rows 0-1, 2-3), each tile's lanes row by row.
    assert tile_order(8, 4).tolist() == [0, 1, 2, 3, 8, 9, 10, 11, 4, 5, 6, 7, 12, 13, 14, 15,
                                         16, 17, 18, 19, 24, 25, 26, 27,
                                         20, 21, 22, 23, 28, 29, 30, 31]
    assert (tile_order(512, 384) == packet_lanes(512, 384).ravel()).all()


def test_tile_order_puts_ragged_edge_tiles_last():
    # 5 x 3 (packet_lanes above): one full tile, then the valid pixels of the three others.
    assert tile_order(5, 3).tolist() == [0, 1, 2, 3, 5, 6, 7, 8, 4, 9, 10, 11, 12, 13, 14]


@pytest.mark.parametrize("w,h", [(1, 1), (3, 1), (4, 2), (5, 3), (7, 5), (8, 6), (12, 1),
                                 (1, 9), (513, 385), (512, 384)])
def test_tile_order_round_trips(w, h):
    order = tile_order(w, h)
    assert order.dtype == np.int64 and sorted(order.tolist()) == list(range(w * h))
    rng = np.random.default_rng(w * 1000 + h)
    rows = rng.standard_normal((w * h, 9)).astype(np.float32)
    rows[::3, 0] = np.inf
    traced = rows[order]  # what lumis returns for the reordered rays
    back = from_tile_order(traced, order)
    assert back.dtype == rows.dtype and (back.view(np.uint32) == rows.view(np.uint32)).all()
    # Every group of 8 that starts within the full tiles is one whole 4 x 2 tile.
    full = int((packet_lanes(w, h) >= 0).all(axis=1).sum())
    for k in range(full):
        ys, xs = np.divmod(order[8 * k:8 * k + 8], w)
        assert xs.min() % 4 == 0 and ys.min() % 2 == 0
        assert (xs - xs.min()).tolist() == [0, 1, 2, 3] * 2
        assert (ys - ys.min()).tolist() == [0] * 4 + [1] * 4
    if w % 4 == 0 and h % 2 == 0:
        assert 8 * full == w * h


def test_packet_groups_counts_shared_origin_and_signs():
    rays = np.zeros((19, 8), np.float32)
    rays[:, 3:6] = [1.0, -1.0, 0.5]
    rays[:, 7] = np.inf
    rays[9, 4] = 1.0  # second group: one ray's y direction flips sign
    rays[17, 0] = 1e-7  # third group (rays 16-18): another origin
    assert packet_groups(rays) == (3, 1)
    rays[17, 0] = 0.0
    assert packet_groups(rays) == (3, 2)
    rays[0:8, 5] = 0.0  # no one sign on z
    assert packet_groups(rays) == (3, 1)
    assert packet_groups(rays[:17]) == (3, 0)  # a last group of one ray is not a packet


def test_same_rows_is_bit_for_bit_and_nan_aware():
    a = np.zeros((3, 9), np.float32)
    a[:, 0] = [1.0, np.inf, np.nan]
    assert same_rows(a, a.copy()) == {"rays": 3, "rows_differ": 0, "columns_differ": [0] * 9}
    b = a.copy()
    b[0, 5] = -0.0
    b[1, 1] = 1.0
    b[1, 8] = 1.0
    assert same_rows(a, b) == {"rays": 3, "rows_differ": 2,
                               "columns_differ": [0, 1, 0, 0, 0, 1, 0, 0, 1]}
    assert same_rows(a, a[:2])["rows_differ"] == 3


def test_header_layout_follows_from_the_field_lists():
    # rtcore_ray.h, 4-byte fields: RTCRay has 12, RTCHit 7 + instID[1] + instPrimID[1] (36,
    # aligned to 16: 48); the 8-wide structs have 8 lanes of each, aligned to 32.
    ray8, hit8 = 12 * 32, (7 + 1 + 1) * 32
    assert HEADER_LAYOUT["sizeof RTCRayHit"] == 48 + 48
    assert HEADER_LAYOUT["sizeof RTCRayHit8"] == ray8 + hit8 == 672
    assert HEADER_LAYOUT["RTCRayHit8.ray.tfar"] == 8 * 32
    assert HEADER_LAYOUT["RTCRayHit8.hit.primID"] == ray8 + 5 * 32
    assert HEADER_LAYOUT["RTCRayHit8.hit.instPrimID"] == ray8 + 8 * 32
    assert HEADER_LAYOUT["RTCRayHit.hit.geomID"] == 48 + 6 * 4
    assert RECORD.itemsize == HEADER_LAYOUT["sizeof record"]


def helper_or_skip(tmp_path):
    try:
        return embree_native.Helper(tmp_path)
    except embree_native.SetupError as e:
        pytest.skip(str(e))


def test_the_compiled_structs_have_the_header_layout(tmp_path):
    # Helper checks this itself; the test states it where a failure names the field.
    assert helper_or_skip(tmp_path).layout() == HEADER_LAYOUT


def records(t, prim, geom):
    r = np.zeros(len(t), RECORD)
    r["t"], r["prim"], r["geom"] = t, prim, geom
    return r


def test_same_hits_compares_t_bit_for_bit():
    inf = np.inf
    a = records([1.0, inf, 0.0, 2.0], [3, -1, 4, 5], [0, -1, 0, 0])
    assert same_hits(a, a.copy()) == {"rays": 4, "t_differs": 0, "prim_differs": 0,
                                      "geom_differs": 0}
    up = np.nextafter(np.float32(2), np.float32(3))  # one float32 ulp above 2
    b = records([1.0, inf, -0.0, up], [3, -1, 4, 6], [0, 0, 0, 0])
    assert same_hits(a, b) == {"rays": 4, "t_differs": 2, "prim_differs": 1, "geom_differs": 1}


def test_lumis_agreement_reads_the_records():
    e = records([1.0, 2.0, np.inf, np.inf], [7, 8, -1, -1], [0, 0, -1, -1])
    lumis_rows = np.full((4, 9), -1.0, np.float32)
    lumis_rows[:, 0] = [1.0, 2.0 * (1 + 1e-6), 3.0, np.inf]  # the third: lumis hits, Embree not
    lumis_rows[:3, 1] = [7, 9, 0]
    a = agreement(as_embreex(e), lumis_rows)
    assert a["same_hit_miss"] == 0.75 and a["both_hit"] == 2
    assert a["same_prim"] == 0.5 and a["t_within_1e-4"] == 1.0


def test_rotation_gives_every_engine_each_place():
    seq = ("a", "b", "c")
    assert [rotated(seq, k) for k in range(4)] == [["a", "b", "c"], ["b", "c", "a"],
                                                   ["c", "a", "b"], ["a", "b", "c"]]


def test_both_loops_find_the_known_hits_of_a_square(tmp_path):
    pytest.importorskip("embreex")
    helper = helper_or_skip(tmp_path)
    # The square [0, 2] x [0, 2] at z = 0 as two triangles (0: lower right, 1: upper left).
    tris = np.array([[[0, 0, 0], [2, 0, 0], [2, 2, 0]], [[0, 0, 0], [2, 2, 0], [0, 2, 0]]],
                    np.float32)
    # A 5 x 3 grid of rays straight down from z = 3 over x = -0.5, 0.25, ..., y = 0.3, 1.3,
    # 2.3: ragged in both directions for 4 x 2 packets.
    w, h = 5, 3
    xs, ys = np.meshgrid(-0.5 + 0.75 * np.arange(w), 0.3 + np.arange(h))
    rays = np.zeros((w * h, 8), np.float32)
    rays[:, 0], rays[:, 1], rays[:, 2] = xs.ravel(), ys.ravel(), 3.0
    rays[:, 5], rays[:, 7] = -1.0, np.inf
    inside = (rays[:, 0] > 0) & (rays[:, 0] < 2) & (rays[:, 1] > 0) & (rays[:, 1] < 2)
    embree = embree_native.NativeEmbree(tris, helper, robust=True)
    try:
        embree.commit()
        one = embree.trace1(rays)[-1]
        eight = embree.trace8(rays, packet_lanes(w, h))[-1]
        coherent = embree.trace8(rays, packet_lanes(w, h), coherent=True)[-1]
    finally:
        embree.close()
    assert (one["t"][inside] == 3.0).all() and np.isinf(one["t"][~inside]).all()
    assert (one["geom"] == np.where(inside, 0, -1)).all()
    lower_right = rays[:, 0] > rays[:, 1]
    assert (one["prim"] == np.where(inside, np.where(lower_right, 0, 1), -1)).all()
    assert np.allclose(one["ng"][inside] / np.abs(one["ng"][inside]).max(1, keepdims=True),
                       [0, 0, 1])
    for other in (eight, coherent):
        assert same_hits(one, other) == {"rays": w * h, "t_differs": 0, "prim_differs": 0,
                                         "geom_differs": 0}
