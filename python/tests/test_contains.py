"""`Scene.contains`: exact even-odd containment of closed meshes and spheres (the surface
inside), the winding number for meshes that are not closed, against oracles that know only
the solids' definitions (trimesh_hard_case.py: exact fractions on the box with a cavity)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import lumis
from trimesh_hard_case import containment, lattice_points, mesh_arrays


def test_box_with_a_cavity_is_exact_on_the_half_unit_lattice():
    vertices, faces = mesh_arrays()
    scene = lumis.Scene.from_arrays(vertices, faces)
    assert scene.containment_methods == ["exact"]
    points = lattice_points(25_000, seed=3)
    want = containment(points)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = scene.contains(points)
    assert got.dtype == np.bool_ and got.shape == (len(points),)
    wrong = np.flatnonzero(got != want)
    assert wrong.size == 0, f"{wrong.size} wrong, e.g. {points[wrong[:5]]}"
    # The lattice puts thousands of points on the surface, inside by the rule.
    assert want.sum() > 5_000 and (~want).sum() > 5_000


def test_threads_and_dtypes_do_not_change_the_answers():
    vertices, faces = mesh_arrays()
    scene = lumis.Scene.from_arrays(vertices, faces)
    points = lattice_points(4_000, seed=5)
    want = scene.contains(points)
    assert np.array_equal(scene.contains(points.astype(np.float32), threads=1), want)
    assert np.array_equal(scene.contains(np.asfortranarray(points), threads=2), want)
    assert np.array_equal(scene.contains(points.tolist()), want)


def test_unwelded_faces_count_as_closed():
    vertices, faces = mesh_arrays()
    # Every triangle its own three vertices, as an STL file stores them.
    soup = vertices[faces].reshape(-1, 3)
    scene = lumis.Scene.from_arrays(soup, np.arange(len(soup)).reshape(-1, 3))
    assert scene.containment_methods == ["exact"]
    points = lattice_points(5_000, seed=7)
    assert np.array_equal(scene.contains(points), containment(points))


def test_an_open_mesh_answers_by_winding_number_and_warns():
    vertices, faces = mesh_arrays()
    # Drop the outer box's top face (z = 8): the cavity stays closed inside, the box is open.
    centroid_z = vertices[faces].mean(axis=1)[:, 2]
    scene = lumis.Scene.from_arrays(vertices, faces[centroid_z != 8])
    assert scene.containment_methods == ["winding_number"]
    deep = np.array([[1, 1, 1], [7, 7, 1], [1, 4, 4.5]], np.float64)  # in the material
    out = np.array([[-1, 4, 4], [4, 4, 12], [3.5, 4, 4.5]], np.float64)  # outside, cavity
    with pytest.warns(lumis.WindingNumberWarning, match="winding number"):
        got = scene.contains(np.vstack([deep, out]))
    assert got.tolist() == [True] * 3 + [False] * 3
    # On the surface of an open mesh: inside, exactly.
    with pytest.warns(lumis.WindingNumberWarning):
        assert scene.contains([[0, 4, 4], [2, 4, 4]]).all()


def test_several_objects_answer_inside_any_and_spheres_exactly():
    vertices, faces = mesh_arrays()
    b = lumis.SceneBuilder()
    b.add_mesh(vertices, faces)
    b.add_sphere([20, 0, 0], 2.0)
    b.add_mesh(vertices + [0, 0, 30], faces)
    scene = b.build()
    assert scene.containment_methods == ["exact"] * 3
    points = np.array(
        [[1, 1, 1], [1, 1, 31], [3.5, 4, 34.5], [20, 0, 2], [20, 0, 2.0000002], [22, 0, 0],
         [21.9999, 0, 0], [10, 10, 10]],
        np.float64,
    )
    assert scene.contains(points).tolist() == [
        True, True, False, True, False, True, True, False]


def test_bad_points_are_refused_by_row():
    scene = lumis.Scene.from_arrays(*mesh_arrays())
    with pytest.raises(ValueError, match=r"points row 1: \[0\.0, NaN, 0\.0\] is not finite"):
        scene.contains(np.array([[0, 0, 0], [0, np.nan, 0]]))
    with pytest.raises(ValueError, match=r"points row 0: .* is not finite as float32"):
        scene.contains(np.array([[1e300, 0, 0]]))
    with pytest.raises(ValueError, match=r"points: shape is \(2, 2\); expected \(N, 3\)"):
        scene.contains(np.zeros((2, 2)))
    assert scene.contains(np.zeros((0, 3))).shape == (0,)
