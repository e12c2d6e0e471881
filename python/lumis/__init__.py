"""lumis from Python: load a scene, trace numpy batches of rays, render to numpy.

The `lumis-rt` distribution of the lumis ray tracer (https://github.com/... `python/`):

>>> import numpy as np, lumis
>>> s = lumis.load("assets/knot.obj")
>>> o = np.zeros((1, 3), np.float32); o[0, 2] = 5
>>> h = s.intersect(o, np.array([[0, 0, -1]], np.float32))
>>> h.t, h.prim_id, h.normal
>>> box = lumis.Scene.from_arrays(vertices, faces)   # numpy (V, 3) and (F, 3)

Ray queries give exactly the answers of `lumis hits` (the same Rust function); renders give
exactly the pixels of `lumis render`'s EXR. Long calls release the GIL and run on rayon's
worker pool, so Python threads can query one scene concurrently. The API is documented in
docs/python.md.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass
from typing import (
    Any,
    Callable,
    Dict,
    Iterable,
    List,
    Mapping,
    Optional,
    Sequence,
    Tuple,
    Union,
    get_args,
)

import numpy as np
import numpy.typing as npt

from . import _contains, _lumis
from ._contains import WindingNumberWarning
from ._defines import define_strings
from ._lumis import RayError, SceneError
from ._types import (
    Accel,
    Aov,
    BoolArray,
    Bound,
    Display,
    Float32Array,
    Int64Array,
    Layout,
    Points,
    Precision,
    Tonemap,
    Up,
)

__all__ = [
    "Accel",
    "AllHits",
    "Aov",
    "Display",
    "Hits",
    "Image",
    "Layout",
    "Precision",
    "Prototype",
    "RayError",
    "Scene",
    "SceneBuilder",
    "SceneError",
    "Tonemap",
    "Up",
    "WindingNumberWarning",
    "load",
]
__version__ = "0.1.0"

PathLike = Union[str, "os.PathLike[str]"]
#: The accelerators (`lumis hits --accel`), the default first.
ACCELS: Tuple[Accel, ...] = get_args(Accel)
#: The primitive tests (`lumis hits --precision`), the default first.
PRECISIONS: Tuple[Precision, ...] = get_args(Precision)


@dataclass(frozen=True)
class Hits:
    """Nearest hits, one entry per ray (the columns of `lumis hits`' `(N, 9)` rows).

    `t` (float32, `inf` for a miss), `prim_id` and `obj_id` (int64, -1 for a miss), `u`, `v`
    (float32 barycentric weights of the triangle's second and third vertex; 0 for spheres and
    misses), `normal` (float32 `(N, 3)`, unit geometric normal: outward for spheres, by winding
    for triangles; 0 for misses), `kind` (int8: 0 sphere, 1 triangle, -1 miss), `inst_id`
    (int64: the instance hit, -1 for a miss or a surface of no instance; `prim_id` is then the
    prototype's primitive, as Embree's `primID` with its `instID`; the column
    `lumis hits --instance-ids` appends).
    """

    t: Float32Array
    prim_id: Int64Array
    obj_id: Int64Array
    u: Float32Array
    v: Float32Array
    normal: Float32Array
    kind: npt.NDArray[np.int8]
    inst_id: Int64Array

    @property
    def hit(self) -> BoolArray:
        """Bool mask of the rays that hit something."""
        return self.prim_id >= 0

    def __len__(self) -> int:
        return len(self.t)

    def as_dict(self) -> Dict[str, npt.NDArray[Any]]:
        """The arrays by name."""
        return dict(self.__dict__)

    def rows(self, instance_ids: bool = False) -> Float32Array:
        """The `(N, 9)` float32 rows `lumis hits --out` writes (ids as float32); with
        `instance_ids`, `(N, 10)` with `inst_id` last, as `lumis hits --instance-ids`."""
        out = np.empty((len(self), 10 if instance_ids else 9), np.float32)
        out[:, 0] = self.t
        out[:, 1] = self.prim_id
        out[:, 2] = self.obj_id
        out[:, 3] = self.u
        out[:, 4] = self.v
        out[:, 5:8] = self.normal
        out[:, 8] = self.kind
        if instance_ids:
            out[:, 9] = self.inst_id
        return out


@dataclass(frozen=True)
class AllHits:
    """Every hit along every ray, one entry per hit: the rows of ray 0 first, then ray 1's,
    and so on, each ray's sorted by `t` (ties by primitive id).

    `ray` (int64) is the index of the ray each hit belongs to; `t`, `prim_id`, `obj_id`, `u`,
    `v`, `normal`, `kind`, `inst_id` are as in `Hits`; `graze` (bool) is true for a touch that
    does not cross the surface (a silhouette edge or vertex, a tangent sphere), false for a
    crossing.
    Each surface crossing is counted once, also where the ray passes through a shared edge or
    vertex (docs/hard-cases.md, "All hits along a ray").
    """

    ray: Int64Array
    t: Float32Array
    prim_id: Int64Array
    obj_id: Int64Array
    u: Float32Array
    v: Float32Array
    normal: Float32Array
    kind: npt.NDArray[np.int8]
    graze: BoolArray
    inst_id: Int64Array

    def __len__(self) -> int:
        return len(self.t)


class Image(Dict[str, npt.NDArray[Any]]):
    """A render: the EXR's channels by name (`R`, `G`, `B`, `A`, `Z`, `N.X`, `N.Y`, `N.Z`,
    `id.object`, `id.prim`, and `albedo.R/G/B`, `P.X/Y/Z`, `uv.U/V`, the light paths
    (`diffuse.R/G/B`, `specular`, `reflection`, `refraction`, `emission`, `ambient`,
    `background`, which add up to RGB) and `light.<name>.R/G/B` when asked; Blender's
    names with `layout="blender"`), each an `(H, W)` array holding exactly the values the EXR
    `lumis render` writes would hold: RGBA as float16 (float32 with `float_rgba=True`),
    linear and already exposed; the rest float32 (ids as float, -1 where the centre ray
    missed; `Z` +inf there). A scene with instances also has `id.instance` (Blender:
    `ViewLayer.IndexInstance.X`): the instance index, -1 on misses and on surfaces of no
    instance. Row 0 is the top of the image.
    """

    #: The exposure applied to RGBA, in stops.
    exposure: float
    #: Whether it was computed from the image (glTF and OBJ files without `exposure=`).
    auto_exposure: bool
    #: What `lumis render` records in the EXR's `lumis/settings` for the same render: `flags`
    #: (the command-line flags that ask for it) and `render` (every render setting, by its
    #: TOML key). `None` for a scene built from arrays, which no command can render again.
    settings: Optional[Dict[str, Any]]

    def rgba(self) -> npt.NDArray[Any]:
        """`(H, W, 4)` RGBA as stored (in either layout)."""
        prefix = "" if "R" in self else "ViewLayer.Combined."
        return np.stack([self[prefix + c] for c in "RGBA"], axis=-1)


def _points(a: npt.ArrayLike) -> Points:
    """An `(N, 3)` array as float32 or float64, converted only when it is neither."""
    array = np.asarray(a)
    if array.dtype == np.float32 or array.dtype == np.float64:
        return array
    return array.astype(np.float64)


def _bound(x: npt.ArrayLike) -> Bound:
    """A `t_min`/`t_max`: a float, or a float32/float64 array."""
    if isinstance(x, (int, float)):
        return float(x)
    a = np.asarray(x)
    if a.ndim == 0:
        return float(a)
    if a.dtype == np.float32 or a.dtype == np.float64:
        return a
    return a.astype(np.float64)


class Scene:
    """A loaded scene (`lumis.load`) or one made from arrays (`Scene.from_arrays`,
    `SceneBuilder`). Its accelerators are built on first use, one per
    (`accel`, `precision`) asked for, and kept; a scene can be queried from several Python
    threads at once.

    Rays: `origins` and `directions` are `(N, 3)` float32 or float64 arrays (read in place:
    any strides, no copy; other dtypes are converted to float64 first); `t_min` and `t_max`
    numbers or `(N,)` arrays. Hits count in `(t_min, t_max]`; `t` is in units of the
    direction's length. Every value is rounded to float32 once (round to nearest, as
    `.astype(numpy.float32)`), which is what `lumis hits` reads from its float32 `.npy` rows,
    so a float64 batch gives exactly the answers of `lumis hits` on `rays.astype(float32)`.
    A ray outside the query domain (non-finite origin, zero or non-finite direction, NaN
    `t_min`/`t_max`) raises `RayError` (a `ValueError`) naming its index; nothing is traced.

    Keyword options: `precision` ("watertight", "fast", "double"; default the scene's
    `precision` setting, as `lumis hits`), `accel` ("sah" default, "brute", "bsp", "bsmp"),
    `threads` (None or 0: one worker per core; the answers do not depend on it).
    """

    __slots__ = ("_s",)

    def __init__(self, inner: _lumis.Scene) -> None:
        self._s = inner

    @classmethod
    def from_arrays(cls, vertices: npt.ArrayLike, faces: npt.ArrayLike) -> "Scene":
        """A scene of one triangle mesh: `vertices` `(V, 3)` float32 or float64 (other real
        dtypes are converted to float64 first), `faces` `(F, 3)` of any integer dtype, both
        read in place (any strides). Object id 0; `prim_id` is the face's row (degenerate
        faces stay, and are never hit). Each coordinate is rounded to float32 once (to
        nearest, as `astype(numpy.float32)`); the answers are exact for that float32 mesh.
        Raises `ValueError` naming the row of a non-finite vertex, a coordinate beyond
        1e18, or a face index out of range. `SceneBuilder` makes scenes of several meshes,
        spheres and instances."""
        builder = SceneBuilder()
        builder.add_mesh(vertices, faces)
        return builder.build()

    def __reduce__(self) -> Tuple[Callable[[Mapping[str, Any]], "Scene"], Tuple[Dict[str, Any]]]:
        from ._builder import scene_from_state

        # A file scene pickles as its path, defines, options and the SHA-256 of every file
        # it read; a scene from arrays as its float32 arrays (see docs/python.md).
        return (scene_from_state, (self._s.pickle_state(),))

    def __repr__(self) -> str:
        source = "from arrays" if self.path is None else repr(self.path)
        return (
            f"<lumis.Scene {source}: {self.num_primitives} primitives, "
            f"{self.num_objects} objects>"
        )

    @property
    def path(self) -> Optional[str]:
        """The file the scene was loaded from (as given); None for a scene from arrays."""
        p = self._s.path
        return None if p is None else str(p)

    @property
    def first_prim(self) -> Int64Array:
        """int64 `(num_objects,)`: the `prim_id` of each object's first primitive (-1 for an
        object without any). A mesh's face `row` is primitive `first_prim[obj_id] + row`;
        on an instance `prim_id` counts the prototype's primitives, so its entry is 0."""
        return self._s.first_prim

    @property
    def num_primitives(self) -> int:
        """Spheres and triangles: `prim_id` runs over `range(num_primitives)`."""
        return self._s.num_primitives

    @property
    def num_objects(self) -> int:
        """Objects: `obj_id` runs over `range(num_objects)`."""
        return self._s.num_objects

    @property
    def settings(self) -> Dict[str, Any]:
        """The scene's render settings after the overrides: width, height, spp (per axis),
        max_depth, exposure, precision."""
        return self._s.settings

    @property
    def warnings(self) -> List[str]:
        """What the loader warned about (`lumis render` prints these)."""
        return self._s.warnings

    def triangles(self) -> Float32Array:
        """Every triangle, float32 `(M, 10)`: primitive id, then the three world-space
        vertices (as `lumis hits --triangles-out`)."""
        return self._s.triangles()

    def spheres(self) -> Float32Array:
        """Every sphere, float32 `(K, 5)`: primitive id, centre xyz, radius (as
        `lumis hits --spheres-out`)."""
        return self._s.spheres()

    def intersect(
        self,
        origins: npt.ArrayLike,
        directions: npt.ArrayLike,
        t_min: npt.ArrayLike = 0.0,
        t_max: npt.ArrayLike = math.inf,
        *,
        precision: Optional[Precision] = None,
        accel: Accel = "sah",
        threads: Optional[int] = None,
    ) -> Hits:
        """The nearest hit of each ray (see the class docs for the arguments): bit for bit
        the rows `lumis hits` writes for the same float32 rays."""
        d = self._s.intersect(
            _points(origins), _points(directions), t_min=_bound(t_min), t_max=_bound(t_max),
            precision=precision, accel=accel, threads=threads,
        )
        return Hits(**d)

    def occluded(
        self,
        origins: npt.ArrayLike,
        directions: npt.ArrayLike,
        t_min: npt.ArrayLike = 0.0,
        t_max: npt.ArrayLike = math.inf,
        *,
        precision: Optional[Precision] = None,
        accel: Accel = "sah",
        threads: Optional[int] = None,
    ) -> BoolArray:
        """Whether anything blocks each ray within `(t_min, t_max]` (bool `(N,)`): the
        any-hit query of `lumis hits --any-hit` (true where its `t` is finite)."""
        return self._s.occluded(
            _points(origins), _points(directions), t_min=_bound(t_min), t_max=_bound(t_max),
            precision=precision, accel=accel, threads=threads,
        )

    def intersect_all(
        self,
        origins: npt.ArrayLike,
        directions: npt.ArrayLike,
        t_min: npt.ArrayLike = 0.0,
        t_max: npt.ArrayLike = math.inf,
        *,
        precision: Optional[Precision] = None,
        accel: Accel = "sah",
        threads: Optional[int] = None,
    ) -> AllHits:
        """Every hit along each ray within `(t_min, t_max]`, each surface crossing counted
        once (also where the ray passes through a shared edge or vertex), plus the grazes
        (`AllHits`): bit for bit the rows of `lumis hits --all` for the same float32 rays. The
        watertight triangle test is used also with `precision="fast"`."""
        d = self._s.intersect_all(
            _points(origins), _points(directions), t_min=_bound(t_min), t_max=_bound(t_max),
            precision=precision, accel=accel, threads=threads,
        )
        return AllHits(**d)

    def contains(self, points: npt.ArrayLike, *, threads: Optional[int] = None) -> BoolArray:
        """Whether each point (`(N, 3)` float32 or float64, rounded to float32 once, as rays
        are) lies inside the scene's solids: bool `(N,)`. Exact for closed meshes (every edge
        shared by an even number of faces, vertices at identical positions counted as one)
        and spheres, with a point on the surface inside (the solid is a closed set); a scene
        of several objects answers "inside any of them". A mesh that is not closed answers by
        its generalized winding number at threshold 1/2, and a `WindingNumberWarning` says
        how many points were answered so (`containment_methods` tells which objects).
        Raises `ValueError` naming the row of a point that is not finite."""
        return _contains.contains(self._s, points, threads)

    @property
    def containment_methods(self) -> List[str]:
        """How each object answers `contains`, by `obj_id`: `"exact"` (a closed mesh or a
        sphere) or `"winding_number"` (a mesh that is not closed)."""
        return _lumis.containment_methods(self._s)


    def render(
        self,
        width: Optional[int] = None,
        height: Optional[int] = None,
        spp: Optional[int] = None,
        *,
        max_depth: Optional[int] = None,
        aovs: Sequence[Aov] = (),
        seed: int = 0,
        threads: Optional[int] = None,
        exposure: Optional[float] = None,
        accel: Accel = "sah",
        precision: Optional[Precision] = None,
        transparent: bool = False,
        float_rgba: bool = False,
        layout: Layout = "lumis",
        tonemap: Tonemap = "none",
        display: Optional[Display] = None,
        path: Union[PathLike, Sequence[PathLike], None] = None,
        display_server: Optional[str] = None,
    ) -> Image:
        """Renders the scene as `lumis render` does with the same options and returns the
        EXR's channels (`Image`): exactly the pixels of `lumis render SCENE -o out.exr` with
        `--width`, `--height`, `--spp` (per axis), `--max-depth`, `--aov`, `--seed`,
        `--exposure`, `--accel`, `--precision`, `--transparent`, `--float`, `--layout`.

        The exposure is `exposure` stops, else the scene's `exposure`, else for glTF and OBJ
        files automatic (as the command). `path`: also write the image to these files (`.exr`
        or `.png` by extension; the PNG through `tonemap` ("none", "filmic") and `display`
        ("srgb", "clamp"; default the scene's)), each replaced only once all were encoded. The
        EXR's pixels are the command's; for a scene loaded from a file its header also has the
        command's provenance (`lumis/sceneHash`, `lumis/seed`, `lumis/settings` with the flags
        that ask for the same render, `lumis/replay`), so `lumis render --from` renders the file
        again (a scene from arrays records none). The image does not depend on
        `threads`. Raises `SceneError` if the render cannot run (a setting out of range).

        `display_server`: "[HOST:]PORT" of a viewer that speaks tev's protocol (tev listens on
        "127.0.0.1:14158"), as `--display-server`: the tiles are streamed as they finish, then
        the image as returned; the image is named after the first `path` (else "lumis"). A
        viewer that cannot be reached or goes away is a `RuntimeWarning`, never an error.
        """
        if path is None:
            paths: List[str] = []
        elif isinstance(path, (str, os.PathLike)):
            paths = [os.fspath(path)]
        else:
            paths = [os.fspath(p) for p in path]
        r = self._s.render(
            width=width, height=height, spp=spp, max_depth=max_depth, aovs=list(aovs),
            seed=seed, threads=threads, exposure=exposure, accel=accel, precision=precision,
            transparent=transparent, float_rgba=float_rgba, layout=layout, tonemap=tonemap,
            display=display, paths=paths, display_server=display_server,
        )
        image = Image()
        for name, plane in r["channels"].items():
            image[name] = plane.view(np.float16) if plane.dtype == np.uint16 else plane
        image.exposure = r["exposure"]
        image.auto_exposure = r["auto_exposure"]
        image.settings = None if r["settings"] is None else json.loads(r["settings"])
        return image


#: Whether `Scene.intersect_all` is available in this build.
ALL_HITS_AVAILABLE: bool = _lumis.ALL_HITS_AVAILABLE


def load(
    path: PathLike,
    defines: Union[Mapping[str, Any], Iterable[str], None] = None,
    *,
    gltf_scene: Optional[int] = None,
    camera: Optional[int] = None,
    up: Optional[Up] = None,
    auto_camera: bool = False,
    frame: Optional[int] = None,
    flatten_instances: bool = False,
    **overrides: Any,
) -> Scene:
    """Loads a scene file (`.toml`, `.scn`, `.obj`, `.gltf`, `.glb`), as `lumis render` does.

    Scene parameters, as `lumis render -D KEY=VALUE`: `defines` (a dict, or `"KEY=VALUE"`
    strings written as on the command line) and then keyword arguments, in order, the last
    winning: `lumis.load("scenes/default.toml", **{"render.spp": 2, "camera.fov": 30})`.
    Values are Python values (bool, int, float, str, lists of them); a str is always a TOML
    string. TOML scenes take any key of their schema, other formats only `render.*` keys.

    `gltf_scene`, `camera` (glTF), `up` ("y" or "z") and `auto_camera` (glTF and OBJ) and
    `frame` (TOML scenes with an `[animation]`) and `flatten_instances` (glTF) are
    `lumis render`'s `--gltf-scene`, `--camera`, `--up`, `--auto-camera`, `--frame` and
    `--flatten-instances` (`Scene.triangles()` holds only flattened triangles, not those of
    instances).

    Raises `SceneError` (a `ValueError`) with the message `lumis` prints after `error: ` when
    the file, a file it references or an override is bad.

    The scene pickles as its absolute path, defines, options and the SHA-256 of every file the
    load read; unpickling reloads it and raises `SceneError` naming a file that changed since.
    """
    inner = _lumis.load(
        os.fspath(path), defines=define_strings(defines, overrides),
        gltf_scene=gltf_scene, camera=camera, up=up, auto_camera=auto_camera, frame=frame,
        flatten_instances=flatten_instances,
    )
    return Scene(inner)


# After `Scene`, which the builder makes.
from ._builder import Prototype, SceneBuilder  # noqa: E402
