"""Scenes from numpy arrays (`SceneBuilder`, `Prototype`) and the rebuilding of a pickled
scene (`scene_from_state`). The checks are the compiled builder's; these wrappers convert
what numpy can convert without changing a value (lists, integer vertices, byte-swapped
arrays) and name the arguments."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, List, Mapping, Optional

import numpy as np
import numpy.typing as npt

from . import _lumis
from ._lumis import SceneError
from ._types import Float64Array, Points

if TYPE_CHECKING:
    from . import Scene


def _vertex_array(a: npt.ArrayLike, what: str) -> Points:
    """`(V, 3)` vertices as float32 or float64 (read in place); other real dtypes become
    float64 first (exact for integers up to 2**53), anything else is refused."""
    array = np.asarray(a)
    if array.dtype.kind not in "biuf":
        raise ValueError(f"{what}: dtype {array.dtype} is not a real number type")
    if array.dtype != np.float32 and array.dtype != np.float64:
        return array.astype(np.float64)
    if not array.dtype.isnative:
        return array.astype(array.dtype.newbyteorder("="))
    return array


def _face_array(a: npt.ArrayLike) -> npt.NDArray[Any]:
    """`(F, 3)` faces, any integer dtype (read in place; byte-swapped ones converted).
    Other dtypes pass through, for the compiled builder to refuse by name."""
    array = np.asarray(a)
    if array.dtype.kind in "iu" and not array.dtype.isnative:
        array = array.astype(array.dtype.newbyteorder("="))
    return array


def _float64(a: npt.ArrayLike, what: str) -> Float64Array:
    """A small array (a centre, a matrix) as float64, or a `ValueError` naming `what`."""
    try:
        return np.asarray(a, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{what}: {e}") from None


class Prototype:
    """A mesh that `SceneBuilder.add_instance` places (returned by `add_prototype`)."""

    __slots__ = ("_builder", "index")

    def __init__(self, builder: "SceneBuilder", index: int) -> None:
        self._builder = builder
        #: Its index among the builder's prototypes.
        self.index = index

    def __repr__(self) -> str:
        return f"<lumis.Prototype {self.index}>"


class SceneBuilder:
    """A scene of several meshes, spheres and instances from arrays, assembled by lumis-core's
    scene builder (the one the file loaders use, so a mesh answers as it would from a file).

    Each add returns the id the queries report: `add_mesh` and `add_sphere` the object's
    `obj_id`, `add_instance` the `inst_id`. Objects are numbered in the order added, an
    instance making one object too (its `obj_id` is the number of `add_mesh`, `add_sphere`
    and `add_instance` calls before it); primitives likewise (a mesh one per face, a sphere
    one, an instance one), and `Scene.first_prim` gives each object's first: a mesh's face
    `row` is `prim_id = first_prim[obj_id] + row`. A hit on an instance reports its
    prototype's face row as `prim_id`. Vertices are rounded to float32 once; matrices are kept
    in float64. Bad input raises `ValueError` naming the argument and the row.

    >>> b = lumis.SceneBuilder()
    >>> ground = b.add_mesh(vertices, faces, name="ground")
    >>> ball = b.add_sphere((0, 1, 0), 0.5)
    >>> bunny = b.add_prototype(bunny_vertices, bunny_faces)
    >>> first = b.add_instance(bunny, np.eye(4))
    >>> scene = b.build()
    """

    __slots__ = ("_b",)

    def __init__(self) -> None:
        self._b = _lumis.SceneBuilder()

    def add_mesh(
        self, vertices: npt.ArrayLike, faces: npt.ArrayLike, *, name: Optional[str] = None
    ) -> int:
        """Adds a triangle mesh object (`vertices` `(V, 3)` float32/float64, `faces` `(F, 3)`
        integers, as `Scene.from_arrays`); returns its `obj_id`."""
        obj_id, _ = self._b.add_mesh(
            vertices=_vertex_array(vertices, "vertices"),
            faces=_face_array(faces), name=name,
        )
        return int(obj_id)

    def add_sphere(
        self, center: npt.ArrayLike, radius: float, *, name: Optional[str] = None
    ) -> int:
        """Adds a sphere object (`center` 3 numbers, `radius` > 0, both rounded to float32);
        returns its `obj_id`."""
        obj_id, _ = self._b.add_sphere(
            center=_float64(center, "center"), radius=float(radius), name=name,
        )
        return int(obj_id)

    def add_prototype(self, vertices: npt.ArrayLike, faces: npt.ArrayLike) -> Prototype:
        """Adds a mesh for instances to place (not drawn by itself); its hierarchy is built
        once, however many instances place it."""
        index = self._b.add_prototype(
            vertices=_vertex_array(vertices, "vertices"), faces=_face_array(faces),
        )
        return Prototype(self, int(index))

    def add_instance(
        self, prototype: Prototype, matrix: npt.ArrayLike, *, name: Optional[str] = None
    ) -> int:
        """Places `prototype` by `matrix`, an affine transform `(4, 4)` (last row
        `[0, 0, 0, 1]`) or `(3, 4)`, row-major as numpy and trimesh write them:
        `world = matrix @ [x, y, z, 1]`. Returns its `inst_id`. A matrix with a non-finite
        entry or no inverse (a zero scale) raises `ValueError`."""
        if not isinstance(prototype, Prototype):
            raise TypeError(
                f"prototype: expected a lumis.Prototype (from add_prototype), got "
                f"{type(prototype).__name__}"
            )
        if prototype._builder is not self:
            raise ValueError("prototype: it belongs to another SceneBuilder")
        inst_id, _ = self._b.add_instance(
            prototype=prototype.index, matrix=_float64(matrix, "matrix"), name=name,
        )
        return int(inst_id)

    def build(self) -> "Scene":
        """The scene (the builder is spent). It renders as a bare OBJ model would: lumis's
        default material, the automatic camera and light rig. Raises `ValueError` naming a
        shape beyond the coordinate limit (an instance placed too far, a sphere too large)."""
        from . import Scene

        return Scene(self._b.build())


def scene_from_state(state: Mapping[str, Any]) -> "Scene":
    """A scene from its pickled form (`Scene.__reduce__`)."""
    kind = state.get("kind")
    from . import Scene

    if kind == "file":
        kwargs = {k: v for k, v in state.items() if k not in ("kind", "path", "defines")}
        defines = list(state["defines"])
        return Scene(_lumis.load(state["path"], defines=defines, **kwargs))
    if kind == "arrays":
        builder = SceneBuilder()
        prototypes: List[Prototype] = []
        for step in state["steps"]:
            op = step["op"]
            if op == "mesh":
                builder.add_mesh(step["vertices"], step["faces"], name=step["name"])
            elif op == "sphere":
                builder.add_sphere(step["center"], step["radius"], name=step["name"])
            elif op == "prototype":
                prototypes.append(builder.add_prototype(step["vertices"], step["faces"]))
            elif op == "instance":
                builder.add_instance(
                    prototypes[step["prototype"]], step["matrix"], name=step["name"]
                )
            else:
                raise SceneError(f"a pickled lumis scene has an unknown step {op!r}")
        return builder.build()
    raise SceneError(f"not a pickled lumis scene (kind {kind!r})")
