"""trimesh's ray interface answered by lumis: a drop-in for
`trimesh.ray.ray_pyembree.RayMeshIntersector` (trimesh 5.2.0) whose answers are exact.

>>> import trimesh, lumis.trimesh
>>> mesh = trimesh.creation.box()
>>> mesh.ray = lumis.trimesh.RayMeshIntersector(mesh)
>>> mesh.ray.intersects_location([[0, 0, -5]], [[0, 0, 1]])   # two crossings
>>> mesh.contains([[0, 0, 0.5]])                               # on the surface: inside

Same constructor, methods, argument names, defaults, return types, dtypes and shapes as the
Embree engine; what differs is what comes back at shared edges and vertices
(docs/python.md, "trimesh"):

- `intersects_id` / `intersects_location` with `multiple_hits=True` list every hit of the
  ray from `Scene.intersect_all`: one row per surface crossing and one per touch (a
  silhouette edge or vertex; trimesh counts a touch as a hit), each once, with no re-query
  offsets. `max_hits` keeps each ray's first `max_hits` hits by distance, as the Embree
  engine's loop does; below the cap nothing is lost. Rows come ray by ray, each ray's by
  distance (the Embree engine orders them by query round).
- Hits count from the origin on (`t >= 0`, as Embree's `tnear = 0`), so a ray starting on the
  surface hits it there.
- Locations are `origin + t * direction` in float64, on the line lumis traced.
- A ray with a zero or non-finite direction, or an origin that is not finite as float32, is a
  miss, as the Embree engine answers it (lumis itself refuses such rays). Directions are used
  as given, whatever their length (the Embree engine misses with one shorter than about 1e-17).
- `contains_points` is `Scene.contains`: the exact answer, a point on the surface inside.

The mesh is rounded to float32 once, as Embree's copy is; the answers are exact for that
mesh. The lumis scene is built on first use and rebuilt when the mesh's vertices or faces
change (trimesh's cache, keyed on the mesh's hash, as the Embree engine's).
"""

from __future__ import annotations

from typing import Any, Dict, Literal, Optional, Tuple, Union, overload

import numpy as np
import numpy.typing as npt
from trimesh import Trimesh, caching, util

from . import Scene, _lumis
from ._types import BoolArray, Float32Array, Float64Array, Int64Array

__all__ = ["RayMeshIntersector"]

# Hits count in (T_MIN, t_max]: the smallest float32 subnormal below zero makes that `t >= 0`
# in float32, so a hit at the origin is reported as Embree reports it (tnear = 0 inclusive).
T_MIN = -(2.0**-149)


class RayMeshIntersector:
    """Ray queries on a `trimesh.Trimesh` through lumis (see the module's docs).

    `scale_to_box` is accepted for compatibility and changes nothing: the Embree engine
    rescales the mesh to a 100-unit box against float32 trouble at extreme scales, while
    lumis's tests are exact at any scale the float32 range holds.
    """

    def __init__(self, geometry: Trimesh, scale_to_box: bool = True) -> None:
        self.mesh = geometry
        self._scale_to_box = scale_to_box
        # trimesh's cache is untyped.
        self._cache = caching.Cache(  # type: ignore[no-untyped-call]
            id_function=self.mesh.__hash__
        )

    @caching.cache_decorator  # type: ignore[untyped-decorator]
    def _scene(self) -> "_MeshScene":
        """The lumis scene of the mesh as it is now (rebuilt when the mesh changes)."""
        return _MeshScene(self.mesh.vertices, self.mesh.faces)

    def intersects_location(
        self,
        ray_origins: npt.ArrayLike,
        ray_directions: npt.ArrayLike,
        multiple_hits: bool = True,
    ) -> Tuple[Float64Array, Int64Array, Int64Array]:
        """Where rays hit the surface: `locations` float64 `(m, 3)`, `index_ray` int64 `(m,)`,
        `index_tri` int64 `(m,)` (indexes of `mesh.faces`)."""
        index_tri, index_ray, locations = self.intersects_id(
            ray_origins=ray_origins,
            ray_directions=ray_directions,
            multiple_hits=multiple_hits,
            return_locations=True,
        )
        return locations, index_ray, index_tri

    @overload
    def intersects_id(
        self,
        ray_origins: npt.ArrayLike,
        ray_directions: npt.ArrayLike,
        multiple_hits: bool = ...,
        max_hits: int = ...,
        return_locations: Literal[False] = ...,
    ) -> Tuple[Int64Array, Int64Array]: ...

    @overload
    def intersects_id(
        self,
        ray_origins: npt.ArrayLike,
        ray_directions: npt.ArrayLike,
        multiple_hits: bool = ...,
        max_hits: int = ...,
        *,
        return_locations: Literal[True],
    ) -> Tuple[Int64Array, Int64Array, Float64Array]: ...

    @overload
    def intersects_id(
        self,
        ray_origins: npt.ArrayLike,
        ray_directions: npt.ArrayLike,
        multiple_hits: bool,
        max_hits: int,
        return_locations: bool,
    ) -> Union[Tuple[Int64Array, Int64Array], Tuple[Int64Array, Int64Array, Float64Array]]: ...

    def intersects_id(
        self,
        ray_origins: npt.ArrayLike,
        ray_directions: npt.ArrayLike,
        multiple_hits: bool = True,
        max_hits: int = 100,
        return_locations: bool = False,
    ) -> Union[Tuple[Int64Array, Int64Array], Tuple[Int64Array, Int64Array, Float64Array]]:
        """The triangles rays hit: `index_tri` int64 `(m,)`, `index_ray` int64 `(m,)` and,
        with `return_locations`, `locations` float64 `(m, 3)`. With `multiple_hits` every
        crossing and touch along each ray, the first `max_hits` of each by distance; without,
        the nearest hit of each ray that hits."""
        rays = _Rays(ray_origins, ray_directions)
        scene = self._scene
        if multiple_hits:
            hits = scene.all_hits(rays.origins, rays.directions)
            ray = rays.index[hits.ray]
            keep = _first_of_each_ray(hits.ray, int(max_hits))
            t, tri, ray = hits.t[keep], hits.tri[keep], ray[keep]
        else:
            t, tri = scene.first_hits(rays.origins, rays.directions)
            hit = tri >= 0
            t, tri, ray = t[hit], tri[hit], rays.index[hit]
        index_tri = tri.astype(np.int64)
        index_ray = ray.astype(np.int64)
        if not return_locations:
            return index_tri, index_ray
        return index_tri, index_ray, rays.locations(index_ray, t)

    def intersects_first(
        self, ray_origins: npt.ArrayLike, ray_directions: npt.ArrayLike
    ) -> npt.NDArray[np.int32]:
        """The nearest triangle each ray hits: int32 `(n,)`, -1 for a miss."""
        rays = _Rays(ray_origins, ray_directions)
        first = np.full(rays.count, -1, dtype=np.int32)
        _, tri = self._scene.first_hits(rays.origins, rays.directions)
        first[rays.index] = tri
        return first

    def intersects_any(
        self, ray_origins: npt.ArrayLike, ray_directions: npt.ArrayLike
    ) -> BoolArray:
        """Whether each ray hits the surface: bool `(n,)`."""
        rays = _Rays(ray_origins, ray_directions)
        hit = np.zeros(rays.count, dtype=bool)
        _, tri = self._scene.first_hits(rays.origins, rays.directions)
        hit[rays.index] = tri >= 0
        return hit

    def contains_points(self, points: npt.ArrayLike) -> BoolArray:
        """Whether each point is inside the mesh: bool `(n,)`, exact for the float32 point
        (`Scene.contains`: a point on the surface is inside). Points that are not finite as
        float32 are outside."""
        points = np.asarray(points, dtype=np.float64)
        if not util.is_shape(points, (-1, 3)):
            raise ValueError("points must be (n,3)")
        contains = np.zeros(len(points), dtype=bool)
        with np.errstate(invalid="ignore"):
            finite = _row_max_abs(points) < _F32_ROUNDS_TO_INF
        if finite.all():
            contains = self._scene.contains(points)
        elif finite.any():
            contains[finite] = self._scene.contains(points[finite])
        return contains

    def __getstate__(self) -> Dict[str, Any]:
        state = self.__dict__.copy()
        state.pop("_cache", None)  # the scene is rebuilt on first use
        return state

    def __setstate__(self, state: Dict[str, Any]) -> None:
        self.__dict__.update(state)
        # trimesh's cache is untyped.
        self._cache = caching.Cache(  # type: ignore[no-untyped-call]
            id_function=self.mesh.__hash__
        )

    def __deepcopy__(self, *args: Any) -> "RayMeshIntersector":
        return self.__copy__()

    def __copy__(self, *args: Any) -> "RayMeshIntersector":
        return RayMeshIntersector(geometry=self.mesh, scale_to_box=self._scale_to_box)


class _Rays:
    """A batch of rays as trimesh takes it, reduced to those lumis can trace: `index` (the
    rows traced), `origins` and `directions` of those rows. Directions beyond 2^+-64 are
    scaled by a power of two, which changes neither the line nor its float32 rounding but
    keeps it within float32's range."""

    def __init__(self, ray_origins: npt.ArrayLike, ray_directions: npt.ArrayLike) -> None:
        origins = np.asarray(ray_origins, dtype=np.float64)
        directions = np.asarray(ray_directions, dtype=np.float64)
        if origins.shape != directions.shape:
            raise ValueError("Ray origin and direction don't match!")
        if not util.is_shape(origins, (-1, 3)):
            raise ValueError("rays must be (n,3)")
        self.count = len(origins)
        with np.errstate(invalid="ignore"):
            # NaN compares false: such rays are not traced.
            reach = _row_max_abs(origins)
            length = _row_max_abs(directions)
            finite = length <= np.finfo(np.float64).max
            traced = (reach < _F32_ROUNDS_TO_INF) & (length > 0) & finite
            rescale = (length < 2.0**-64) | (length > 2.0**64)
        self.all_traced = bool(traced.all())
        if self.all_traced:
            self.index = np.arange(self.count)
        else:
            self.index = np.flatnonzero(traced)
            origins, directions = origins[self.index], directions[self.index]
            rescale = rescale[self.index]
        if rescale.any():
            directions = np.array(directions)
            _, exponent = np.frexp(np.abs(directions[rescale]).max(axis=1))
            directions[rescale] = np.ldexp(directions[rescale], -exponent[:, None])
        self.origins, self.directions = origins, directions

    def locations(self, index_ray: Int64Array, t: Float32Array) -> Float64Array:
        """`origin + t * direction` in float64 for hits of rows `index_ray` at `t`."""
        row = index_ray if self.all_traced else np.searchsorted(self.index, index_ray)
        return self.origins[row] + t.astype(np.float64)[:, None] * self.directions[row]


def _row_max_abs(a: Float64Array) -> Float64Array:
    """Largest magnitude of each row of an `(n, 3)` array, NaN where a row has one (numpy's
    row reductions are several times slower on rows of three)."""
    largest: Float64Array = np.maximum(
        np.maximum(np.abs(a[:, 0]), np.abs(a[:, 1])), np.abs(a[:, 2])
    )
    return largest


# The smallest magnitude that rounds to an infinite float32: float32's largest value plus
# half its last step.
_F32_ROUNDS_TO_INF = 2.0**128 - 2.0**103


def _first_of_each_ray(ray: Int64Array, max_hits: int) -> BoolArray:
    """Mask of the first `max_hits` entries of each ray in `ray` (grouped, in order)."""
    if len(ray) == 0 or max_hits <= 0:
        return np.zeros(len(ray), dtype=bool)
    if np.bincount(ray).max() <= max_hits:
        return np.ones(len(ray), dtype=bool)
    starts = np.r_[0, np.flatnonzero(ray[1:] != ray[:-1]) + 1]
    lengths = np.diff(np.r_[starts, len(ray)])
    rank = np.arange(len(ray)) - np.repeat(starts, lengths)
    first: BoolArray = rank < max_hits
    return first


class _AllHits:
    __slots__ = ("ray", "t", "tri")

    def __init__(self, ray: Int64Array, t: Float32Array, tri: Int64Array) -> None:
        self.ray, self.t, self.tri = ray, t, tri


class _MeshScene:
    """One triangle mesh as a lumis scene (`Scene.from_arrays`: `prim_id` is the face's row);
    a mesh without faces answers misses."""

    def __init__(self, vertices: npt.ArrayLike, faces: npt.ArrayLike) -> None:
        faces = np.asarray(faces)
        self.scene: Optional[Scene] = None
        if len(faces) == 0:
            return
        self.scene = Scene.from_arrays(np.asarray(vertices), faces)

    def first_hits(
        self, origins: Float64Array, directions: Float64Array
    ) -> Tuple[Float32Array, Int64Array]:
        """`t` and face of each ray's nearest hit (face -1 for a miss), exact on each ray's
        own line: the nearest-hit query is, for origins near the mesh (where it traces the
        ray as given, and its answer is the first of all hits bit for bit); a ray from
        farther away is answered by the first of its exact all hits instead, since the
        nearest-hit query moves such an origin near the mesh, rounding it, and a ray that
        only touches an edge could then miss it (docs/hard-cases.md)."""
        if self.scene is None or len(origins) == 0:
            miss = np.full(len(origins), -1, np.int64)
            return np.full(len(origins), np.inf, np.float32), miss
        h = self.scene.intersect(origins, directions, t_min=T_MIN)
        t, face = h.t, h.prim_id
        far = np.flatnonzero(~_lumis.near_origins(self.scene._s, origins))
        if far.size:
            a = self.scene.intersect_all(origins[far], directions[far], t_min=T_MIN)
            rays, first = np.unique(a.ray, return_index=True)
            t[far] = np.inf
            face[far] = -1
            t[far[rays]] = a.t[first]
            face[far[rays]] = a.prim_id[first]
        return t, face

    def all_hits(self, origins: Float64Array, directions: Float64Array) -> _AllHits:
        """Every hit (crossings and grazes), ray by ray, each ray's by `t`."""
        if self.scene is None or len(origins) == 0:
            empty = np.zeros(0, dtype=np.int64)
            return _AllHits(empty, np.zeros(0, np.float32), empty)
        h = self.scene.intersect_all(origins, directions, t_min=T_MIN)
        return _AllHits(h.ray, h.t, h.prim_id)

    def contains(self, points: Float64Array) -> BoolArray:
        if self.scene is None or len(points) == 0:
            return np.zeros(len(points), dtype=bool)
        return np.asarray(self.scene.contains(points), dtype=bool)
