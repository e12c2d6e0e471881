"""`lumis.Scene.from_arrays`: known answers, every dtype and layout read alike, rounding to
float32 once, degenerate faces kept as primitives, bad arrays refused by row, and bit-identity
with the same mesh written to an OBJ file and loaded (ids mapped where the OBJ loader drops the
degenerate faces)."""

from __future__ import annotations

import numpy as np
import pytest

import lumis
from conftest import bits
from mesh_cases import (
    aimed_rays, degenerate_faces, mix_in, split_box, write_obj, zero_area,
)

HIT_COLUMNS = ("t", "u", "v", "normal")


def test_known_hits_on_a_box():
    v, f = split_box(2)
    s = lumis.Scene.from_arrays(v, f)
    assert s.path is None and "from arrays" in repr(s)
    assert (s.num_primitives, s.num_objects) == (len(f), 1)
    tri = s.triangles()
    # Primitive k is face row k, its vertices as given.
    assert np.array_equal(tri[:, 0], np.arange(len(f)))
    assert np.array_equal(tri[:, 1:].reshape(-1, 3, 3), v[f].astype(np.float32))
    o = np.array([[0.5, 0.25, 5], [0.5, 0.25, -5], [9, 9, 9]], np.float32)
    d = np.array([[0, 0, -1], [0, 0, 1], [1, 0, 0]], np.float32)
    h = s.intersect(o, d)
    assert list(h.t) == [3.0, 5.0, np.inf]
    assert list(h.obj_id) == [0, 0, -1]
    assert list(h.kind) == [1, 1, -1]
    # The face hit holds the point, and the normal points out of the box.
    for k in range(2):
        p = o[k] + h.t[k] * d[k]
        face = v[f[h.prim_id[k]]]
        assert np.all(face.min(axis=0) <= p) and np.all(p <= face.max(axis=0))
    assert h.normal[0].tolist() == [0, 0, 1] and h.normal[1].tolist() == [0, 0, -1]
    assert list(s.first_prim) == [0]
    assert s.occluded(o, d).tolist() == [True, True, False]
    a = s.intersect_all(o, d)
    assert a.ray.tolist() == [0, 0, 1, 1] and a.t.tolist() == [3, 5, 5, 7]


INT_TYPES = [np.int8, np.int16, np.int32, np.int64, np.uint8, np.uint16, np.uint32, np.uint64]


@pytest.mark.parametrize("ftype", INT_TYPES, ids=lambda t: np.dtype(t).name)
@pytest.mark.parametrize("vtype", [np.float32, np.float64, np.int64, np.float16])
def test_every_dtype_answers_alike(vtype, ftype):
    v, f = split_box(2)
    o, d = aimed_rays(v, f, 200, seed=1)
    ref = lumis.Scene.from_arrays(v.astype(np.float32), f).intersect(o, d)
    got = lumis.Scene.from_arrays(v.astype(vtype), f.astype(ftype)).intersect(o, d)
    for c in HIT_COLUMNS:
        assert np.array_equal(bits(getattr(ref, c)), bits(getattr(got, c))), c
    assert np.array_equal(ref.prim_id, got.prim_id)


def test_strided_and_listed_arrays_read_alike():
    v, f = split_box(2)
    o, d = aimed_rays(v, f, 200, seed=2)
    ref = lumis.Scene.from_arrays(v, f).intersect(o, d)
    wide = np.zeros((len(v), 7))
    wide[:, 1:7:2] = v
    layouts = [
        (np.asfortranarray(v), np.asfortranarray(f)),
        (wide[:, 1:7:2], np.ascontiguousarray(f[:, ::-1])[:, ::-1]),
        (v[::-1][::-1], f.astype(">i4")),
        (v.tolist(), f.tolist()),
        (v.astype(">f8"), f),
    ]
    for vv, ff in layouts:
        h = lumis.Scene.from_arrays(vv, ff).intersect(o, d)
        assert np.array_equal(bits(h.t), bits(ref.t)) and np.array_equal(h.prim_id, ref.prim_id)


def test_float64_vertices_are_rounded_to_float32_once():
    rng = np.random.default_rng(3)
    v = rng.normal(size=(50, 3)) * 10.0 ** rng.integers(-3, 6, size=(50, 1))
    f = rng.integers(0, 50, size=(80, 3))
    s = lumis.Scene.from_arrays(v, f)
    assert np.array_equal(bits(s.triangles()[:, 1:]), bits(v.astype(np.float32)[f].reshape(-1, 9)))
    # Far from the origin the float32 grid is coarse: 1e7 + 0.3 is stored as 1e7.
    far = np.array([[1e7 + 0.3, 0, 0], [1e7, 1, 0], [1e7, 0, 1]])
    t = lumis.Scene.from_arrays(far, [[0, 1, 2]]).triangles()
    assert t[0, 1] == np.float32(1e7)


def test_degenerate_faces_stay_primitives_and_are_never_hit():
    v, f = split_box(2)
    faces, keep = mix_in(f, degenerate_faces(v), seed=4)
    s = lumis.Scene.from_arrays(v, faces)
    assert s.num_primitives == len(faces)
    o, d = aimed_rays(v, faces, 2000, seed=5)
    hit = s.intersect(o, d).prim_id
    all_hits = s.intersect_all(o, d).prim_id
    dead = np.flatnonzero(~keep)
    assert not np.isin(hit, dead).any() and not np.isin(all_hits, dead).any()


def test_empty_arrays_make_an_empty_scene():
    for v, f in [(np.zeros((0, 3)), np.zeros((0, 3), int)), (np.eye(3), np.zeros((0, 3), int))]:
        s = lumis.Scene.from_arrays(v, f)
        assert s.num_primitives == 0
        o = np.zeros((2, 3), np.float32)
        d = np.array([[1, 0, 0], [0, 0, 1]], np.float32)
        assert s.intersect(o, d).t.tolist() == [np.inf, np.inf]
        assert not s.occluded(o, d).any() and len(s.intersect_all(o, d)) == 0


TRI = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float64)
BAD = [
    (np.zeros((3, 2)), [[0, 1, 2]], r"vertices: shape is \(3, 2\); expected \(V, 3\)"),
    (np.zeros(9), [[0, 1, 2]], r"vertices: shape is \(9,\); expected \(V, 3\)"),
    (np.array([["a", "b", "c"]] * 3), [[0, 1, 2]], r"vertices: dtype <U1 is not a real"),
    (np.array([[1 + 1j, 0, 0]] * 3), [[0, 1, 2]], r"vertices: dtype complex128"),
    (np.array([[0, 0, 0], [1, np.nan, 0], [0, 1, 0]]), [[0, 1, 2]],
     r"vertices row 1: \[1\.0, NaN, 0\.0\] is not finite"),
    (np.array([[0, 0, 0], [1, 0, 0], [0, -np.inf, 0]], np.float32), [[0, 1, 2]],
     r"vertices row 2: .*inf.* is not finite"),
    (np.array([[0, 0, 0], [1, 0, 0], [0, 2e18, 0]]), [[0, 1, 2]],
     r"vertices row 2: coordinate 2e18 \(float32 2e18\) exceeds the scene's coordinate limit"),
    (np.array([[0, 0, 0], [1, 0, 0], [0, 1e300, 0]]), [[0, 1, 2]],
     r"vertices row 2: coordinate 1e300 \(float32 inf\) exceeds"),
    (TRI, [[0, 1, 3]], r"faces row 0: index 3 is out of range for 3 vertices"),
    (TRI, [[0, 1, 2], [2, -1, 0]], r"faces row 1: index -1 is negative .*V = 3"),
    (TRI, np.array([[0, 1, 2], [0, 1, 2**40]], np.uint64), r"faces row 1: index 1099511627776"),
    (TRI, [[0, 1]], r"faces: shape is \(1, 2\); expected \(F, 3\)"),
    (TRI, [0, 1, 2], r"faces: shape is \(3,\); expected \(F, 3\)"),
    (TRI, [[0.0, 1.0, 2.0]], r"faces: dtype float64 is not an integer type"),
    (TRI, [[True, False, True]], r"faces: dtype bool is not an integer type"),
]


@pytest.mark.parametrize("v, f, message", BAD, ids=range(len(BAD)))
def test_bad_arrays_are_refused_by_row(v, f, message):
    with pytest.raises(ValueError, match=message):
        lumis.Scene.from_arrays(v, f)


def test_a_scene_from_arrays_renders():
    v, f = split_box(2)
    image = lumis.Scene.from_arrays(v, f).render(8, 6, 1)
    assert image["R"].shape == (6, 8) and image.auto_exposure
    assert (image["id.object"] == 0).any()


@pytest.mark.parametrize("precision", ["watertight", "double", "fast"])
def test_bit_identical_to_the_same_mesh_from_an_obj_file(tmp_path, precision):
    """The mesh with degenerate faces mixed in, from arrays and from an OBJ file (whose
    loader drops the degenerate faces): every column of every nearest and all-hits answer is
    the same, bit for bit, once the OBJ's primitive ids are mapped to the array rows."""
    v, f = split_box(3)
    faces, keep = mix_in(f, degenerate_faces(v), seed=6)
    # Half-unit offsets and a scale keep the float32 values exact but not integers.
    v = v * 0.75 - 1.125
    assert np.array_equal(~keep, zero_area(v / 0.375 + 3, faces))
    arrays = lumis.Scene.from_arrays(v, faces)
    obj = lumis.load(write_obj(tmp_path / "box.obj", v, faces))
    assert obj.num_primitives == keep.sum()
    row_of = np.flatnonzero(keep)  # OBJ primitive k is array row row_of[k]

    o, d = aimed_rays(v, f, 3000, seed=7)
    a = arrays.intersect(o, d, precision=precision)
    b = obj.intersect(o, d, precision=precision)
    assert a.hit.sum() > 1000
    assert np.array_equal(a.hit, b.hit)
    assert np.array_equal(a.prim_id[a.hit], row_of[b.prim_id[b.hit]])
    for c in HIT_COLUMNS + ("kind", "obj_id"):
        assert np.array_equal(bits(getattr(a, c)), bits(getattr(b, c))), c
    assert np.array_equal(arrays.occluded(o, d), obj.occluded(o, d))

    a = arrays.intersect_all(o, d, precision=precision)
    b = obj.intersect_all(o, d, precision=precision)
    assert len(a) == len(b) > 1000
    assert np.array_equal(a.ray, b.ray) and np.array_equal(a.graze, b.graze)
    assert np.array_equal(a.prim_id, row_of[b.prim_id])
    for c in HIT_COLUMNS:
        assert np.array_equal(bits(getattr(a, c)), bits(getattr(b, c))), c
