"""The public API with its types: the three ways in (a file, arrays, trimesh), ray queries,
containment and a render. `mypy --strict python/examples/typed_usage.py` passes
(python/tests/test_typing.py checks it and runs this file); run it from anywhere:
`python python/examples/typed_usage.py`.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import List, Tuple

import numpy as np
import numpy.typing as npt

import lumis

ROOT = Path(__file__).resolve().parents[2]

# A closed box with its corners at 0 and 1: eight vertices, twelve triangles.
CORNERS: npt.NDArray[np.float64] = np.array(
    [[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)]
)
FACES: npt.NDArray[np.int32] = np.array(
    [
        [0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5],  # x = 0, x = 1
        [0, 4, 5], [0, 5, 1], [2, 3, 7], [2, 7, 6],  # y = 0, y = 1
        [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3],  # z = 0, z = 1
    ],
    dtype=np.int32,
)


def rays_along_z(n: int) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
    """`n` rays from below the box straight up, through its inside."""
    xy = (np.arange(n, dtype=np.float32) + 0.5) / n
    origins = np.stack([xy, xy, np.full(n, -1.0, np.float32)], axis=1)
    directions = np.tile(np.array([0.0, 0.0, 1.0], np.float32), (n, 1))
    return origins, directions


def from_a_file() -> lumis.Scene:
    accel: lumis.Accel = "bsp"
    scene = lumis.load(ROOT / "assets" / "knot.obj", {"render.spp": 1}, up="y")
    # Down onto the centroid of the first triangle (id, then three vertices), from above.
    first: npt.NDArray[np.float32] = scene.triangles()[0, 1:].reshape(3, 3)
    origins = first.mean(axis=0, keepdims=True) + np.float32(50.0) * np.array([[0, 0, 1]])
    hits: lumis.Hits = scene.intersect(origins, [[0.0, 0.0, -1.0]], accel=accel)
    assert hits.kind[0] == 1 and hits.t[0] < 51.0
    return scene


def from_arrays() -> Tuple[lumis.Scene, int]:
    builder = lumis.SceneBuilder()
    box: int = builder.add_mesh(CORNERS, FACES, name="box")
    builder.add_sphere((3.0, 0.5, 0.5), 0.5, name="ball")
    prototype: lumis.Prototype = builder.add_prototype(CORNERS, FACES)
    matrix = np.eye(4)
    matrix[:3, 3] = (0.0, 3.0, 0.0)
    first_instance: int = builder.add_instance(prototype, matrix, name="copy")
    scene = builder.build()
    assert scene.num_objects == 3 and first_instance == 0
    return scene, box


def queries(scene: lumis.Scene, box: int) -> None:
    origins, directions = rays_along_z(4)
    precision: lumis.Precision = "watertight"
    nearest = scene.intersect(origins, directions, 0.0, math.inf, precision=precision)
    t: npt.NDArray[np.float32] = nearest.t
    assert np.all(t == 1.0) and np.all(nearest.obj_id == box)
    every: lumis.AllHits = scene.intersect_all(origins, directions, t_max=10.0, threads=1)
    counts: npt.NDArray[np.intp] = np.bincount(every.ray, minlength=len(origins))
    assert counts.tolist() == [2, 2, 2, 2] and not every.graze.any()
    blocked: npt.NDArray[np.bool_] = scene.occluded(origins, directions, t_max=0.5)
    assert not blocked.any()
    points = [[0.5, 0.5, 0.5], [0.5, 0.5, 1.0], [2.0, 2.0, 2.0]]
    inside: npt.NDArray[np.bool_] = scene.contains(points)
    assert inside.tolist() == [True, True, False]  # a point on the surface is inside
    assert scene.containment_methods == ["exact", "exact", "exact"]
    alone = lumis.Scene.from_arrays(CORNERS, FACES)
    rows: npt.NDArray[np.float32] = alone.intersect(origins, directions).rows()
    assert rows.shape == (4, 9)


def render(scene: lumis.Scene) -> float:
    aovs: List[lumis.Aov] = ["albedo", "uv"]
    layout: lumis.Layout = "lumis"
    tonemap: lumis.Tonemap = "filmic"
    display: lumis.Display = "srgb"
    image: lumis.Image = scene.render(
        16, 12, 1, aovs=aovs, layout=layout, tonemap=tonemap, display=display, seed=3
    )
    rgba: npt.NDArray[np.generic] = image.rgba()
    assert rgba.shape == (12, 16, 4) and "albedo.R" in image and "uv.U" in image
    return image.exposure


def through_trimesh() -> None:
    try:
        import trimesh
    except ImportError:  # trimesh is optional
        return
    import lumis.trimesh

    mesh = trimesh.Trimesh(vertices=CORNERS, faces=FACES)
    engine = lumis.trimesh.RayMeshIntersector(mesh)
    origins, directions = rays_along_z(3)
    locations, index_ray, index_tri = engine.intersects_location(origins, directions)
    assert len(locations) == 6 and index_ray.dtype == np.int64 and len(index_tri) == 6
    first: npt.NDArray[np.int32] = engine.intersects_first(origins, directions)
    assert (first >= 0).all()


def main() -> int:
    from_a_file()
    scene, box = from_arrays()
    queries(scene, box)
    exposure = render(scene)
    through_trimesh()
    print(f"typed usage: ok (auto exposure {exposure:+.2f} EV)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
