"""`lumis.SceneBuilder`: the ids each add returns are the ids the queries report (objects,
primitives through `Scene.first_prim`, instances), spheres and instances answer as an
independent float64 computation says, and bad input is refused by name."""

from __future__ import annotations

import numpy as np
import pytest

import lumis
from mesh_cases import split_box

QUAD_V = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float64)
QUAD_F = np.array([[0, 1, 2], [0, 2, 3]])


def down(xy, z=10.0):
    """float32 rays straight down -z at the points `xy`."""
    xy = np.asarray(xy, np.float64)
    o = np.column_stack([xy, np.full(len(xy), z)]).astype(np.float32)
    d = np.tile(np.array([0, 0, -1], np.float32), (len(xy), 1))
    return o, d


def test_ids_returned_are_the_ids_reported():
    b = lumis.SceneBuilder()
    box_v, box_f = split_box(1)
    quad = b.add_mesh(QUAD_V + [0, 0, -5], QUAD_F, name="floor")
    ball = b.add_sphere([10, 0, 0], 1.0, name="ball")
    box = b.add_mesh(box_v + [20, 0, 0], box_f)
    proto = b.add_prototype(QUAD_V, QUAD_F)
    # Two placements: a shift to x = 30, and a 90-degree turn about z plus a shift to x = 40.
    shift = np.eye(4)
    shift[0, 3] = 30
    turn = np.array([[0, -1, 0, 40], [0, 1 * 0 + 1 * 0, 0, 0], [0, 0, 1, 0]], np.float64)
    turn[1, 0] = 1
    first = b.add_instance(proto, shift)
    second = b.add_instance(proto, turn, name="turned")
    s = b.build()
    assert (quad, ball, box, first, second) == (0, 1, 2, 0, 1)
    assert s.num_objects == 5
    # Primitives: 2 quad faces, 1 sphere, 12 box faces, then one per instance.
    assert s.num_primitives == 2 + 1 + 12 + 2
    assert s.first_prim.tolist() == [0, 2, 3, 0, 0]

    o, d = down([(0.5, -0.5), (10, 0), (20.25, 0.5), (30.5, 0.25), (39.75, 0.5), (50, 0)])
    h = s.intersect(o, d)
    assert h.obj_id.tolist() == [0, 1, 2, 3, 4, -1]
    assert h.inst_id.tolist() == [-1, -1, -1, 0, 1, -1]
    assert h.kind.tolist() == [0 + 1, 0, 1, 1, 1, -1]
    assert h.t.tolist()[:5] == [15, 9, 9, 10, 10]
    # The quad's face row: (0.5, -0.5) is in face 0 ([0,1,2]: below the diagonal y = x).
    assert h.prim_id[0] - s.first_prim[0] == 0
    # The box's top face (z = 1) is hit; prim_id - first_prim is that face's row.
    row = h.prim_id[2] - s.first_prim[2]
    assert (box_v[box_f[row]][:, 2] == 1).all()
    # The instances report their prototype's face row: (0.5, 0.25) is in face 0; under the
    # turn, world (39.75, 0.5) is object (0.5, 0.25) too.
    assert h.prim_id[3] == 0 and h.prim_id[4] == 0
    o2, d2 = down([(30.25, 0.5)])
    assert s.intersect(o2, d2).prim_id.tolist() == [1]


def test_3x4_and_4x4_matrices_place_alike():
    m = np.array([[2, 0, 0, 1], [0, 1, 0, 2], [0, 0, 0.5, 3], [0, 0, 0, 1]], np.float64)
    scenes = []
    for matrix in (m, m[:3], m.tolist()):
        b = lumis.SceneBuilder()
        b.add_instance(b.add_prototype(QUAD_V, QUAD_F), matrix)
        scenes.append(b.build())
    o, d = down([(1.5, 2.5), (2.9, 2.9), (3.5, 2)])
    hits = [s.intersect(o, d) for s in scenes]
    # world = M @ [x, y, 0, 1]: the quad spans x in [-1, 3], y in [1, 3], at z = 3.
    assert hits[0].t.tolist() == [7, 7, np.inf]
    for h in hits[1:]:
        assert np.array_equal(h.t, hits[0].t) and np.array_equal(h.prim_id, hits[0].prim_id)


def test_spheres_answer_as_float64_says():
    rng = np.random.default_rng(8)
    b = lumis.SceneBuilder()
    centres = rng.uniform(-20, 20, size=(6, 3))
    radii = rng.uniform(0.5, 3, size=6)
    for c, r in zip(centres, radii):
        b.add_sphere(c, r)
    s = b.build()
    spheres = s.spheres()
    assert np.array_equal(spheres[:, 1:4], centres.astype(np.float32))
    assert np.array_equal(spheres[:, 4], radii.astype(np.float32))
    # Rays from far away at each centre: the nearest root of |o + t d - c| = r, in float64
    # from the float32 values, is what lumis finds (within float32 rounding).
    o = (centres + rng.normal(size=(6, 3)) * 60).astype(np.float32)
    c64, r64 = spheres[:, 1:4].astype(np.float64), spheres[:, 4].astype(np.float64)
    d = (c64 - o).astype(np.float32)
    h = s.intersect(o, d)
    assert h.obj_id.tolist() == list(range(6)) or (h.kind == 0).all()
    for k in range(6):
        j = h.obj_id[k]
        oc = o[k].astype(np.float64) - c64[j]
        dd = d[k].astype(np.float64)
        a, bq, cq = dd @ dd, 2 * oc @ dd, oc @ oc - r64[j] ** 2
        t = (-bq - np.sqrt(bq * bq - 4 * a * cq)) / (2 * a)
        assert abs(h.t[k] - t) <= 4e-7 * t


def test_a_builder_with_nothing_builds_an_empty_scene():
    s = lumis.SceneBuilder().build()
    assert (s.num_primitives, s.num_objects) == (0, 0)
    o, d = down([(0, 0)])
    assert s.intersect(o, d).t.tolist() == [np.inf]


def test_bad_builder_input_is_refused_by_name():
    b = lumis.SceneBuilder()
    proto = b.add_prototype(QUAD_V, QUAD_F)
    cases = [
        (lambda: b.add_sphere([0, 0, 0], 0.0), r"radius: 0\.0 must be finite and > 0"),
        (lambda: b.add_sphere([0, 0, 0], -1), r"radius: -1\.0 must be finite and > 0"),
        (lambda: b.add_sphere([0, 0, 0], np.nan), r"radius: NaN must be finite"),
        (lambda: b.add_sphere([0, 0, 0], 1e-50), r"radius: 1e-50 .*as float32: 0e0"),
        (lambda: b.add_sphere([0, np.inf, 0], 1), r"center: \[0\.0, inf, 0\.0\] is not finite"),
        (lambda: b.add_sphere([0, 5e18, 0], 1), r"center: .*exceeds the scene's coordinate"),
        (lambda: b.add_sphere([0, 0], 1), r"center: shape is \(2,\); expected \(3,\)"),
        (lambda: b.add_sphere("abc", 1), r"center: could not convert"),
        (lambda: b.add_instance(proto, np.diag([1.0, 0.0, 1.0, 1.0])),
         r"matrix: the transform is singular \(determinant 0e0\)"),
        (lambda: b.add_instance(proto, np.full((3, 4), np.nan)),
         r"matrix: the transform has a non-finite entry"),
        (lambda: b.add_instance(proto, np.ones((4, 4))),
         r"matrix: last row is \[1\.0, 1\.0, 1\.0, 1\.0\]; an affine transform's is \[0, 0, 0, 1\]"),
        (lambda: b.add_instance(proto, np.eye(3)), r"matrix: shape is \(3, 3\); expected \(4, 4\) or \(3, 4\)"),
        (lambda: b.add_instance(proto, np.eye(5)[:, :4]), r"matrix: shape is \(5, 4\)"),
        (lambda: b.add_instance(lumis.SceneBuilder().add_prototype(QUAD_V, QUAD_F), np.eye(4)),
         r"prototype: it belongs to another SceneBuilder"),
        (lambda: b.add_mesh(QUAD_V, [[0, 1, 4]]), r"faces row 0: index 4 is out of range for 4"),
        (lambda: b.add_prototype(QUAD_V, [[0, -2, 1]]), r"faces row 0: index -2 is negative"),
    ]
    for call, message in cases:
        with pytest.raises(ValueError, match=message):
            call()
    with pytest.raises(TypeError, match="expected a lumis.Prototype"):
        b.add_instance(0, np.eye(4))
    # The refusals left nothing behind: the builder still builds what was added.
    s = b.build()
    assert s.num_primitives == 0
    with pytest.raises(RuntimeError, match="built"):
        b.add_mesh(QUAD_V, QUAD_F)
    with pytest.raises(RuntimeError, match="built"):
        b.build()


def test_shapes_beyond_the_coordinate_limit_are_refused_at_build_by_name():
    b = lumis.SceneBuilder()
    far = np.eye(4)
    far[0, 3] = 9e17
    b.add_instance(b.add_prototype(QUAD_V * 2e17, QUAD_F), far, name="far away")
    with pytest.raises(ValueError, match=r'instance "far away": world-space bounds .* exceed'):
        b.build()
    b = lumis.SceneBuilder()
    b.add_sphere([9e17, 0, 0], 5e17, name="big")
    with pytest.raises(ValueError, match=r'sphere "big": world-space bounds'):
        b.build()
