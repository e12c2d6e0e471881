"""Type stubs of the compiled module `lumis._lumis` (use the `lumis` package's API).

Each signature here is the Rust `#[pyo3(signature = ...)]` of python/src/*.rs, checked by
`python -m mypy.stubtest lumis._lumis` (python/tests/test_typing.py); mypy checks the calls
the package's Python modules make against it.
"""

from os import PathLike
from typing import Any, Dict, List, Optional, Sequence, Tuple, TypedDict, Union, final

import numpy as np
import numpy.typing as npt

from ._types import (
    Accel,
    Aov,
    BoolArray,
    Bound,
    Display,
    Float32Array,
    Float64Array,
    Int64Array,
    Layout,
    Points,
    Precision,
    Tonemap,
    Up,
)

# PyO3 sets the module's `__all__` to what the module adds, in that order.
__all__ = [
    "load",
    "contains",
    "containment_methods",
    "near_origins",
    "Scene",
    "SceneBuilder",
    "SceneError",
    "RayError",
    "HIT_COLUMNS",
    "ALL_HITS_AVAILABLE",
    "CHOICES",
]

HIT_COLUMNS: int
ALL_HITS_AVAILABLE: bool
#: The names each option takes, from the library's types ("accel", "precision", "up",
#: "layout", "tonemap", "display", "aov").
CHOICES: Dict[str, List[str]]

class SceneError(ValueError): ...
class RayError(ValueError): ...

class _HitColumns(TypedDict):
    t: Float32Array
    prim_id: Int64Array
    obj_id: Int64Array
    u: Float32Array
    v: Float32Array
    normal: Float32Array
    kind: npt.NDArray[np.int8]
    inst_id: Int64Array

class _AllHitColumns(_HitColumns):
    ray: Int64Array
    graze: BoolArray

class _Rendered(TypedDict):
    # Half floats come as their uint16 bits (the package views them as float16).
    channels: Dict[str, npt.NDArray[Union[np.uint16, np.float32, np.uint32]]]
    exposure: float
    auto_exposure: bool
    settings: Optional[str]

@final
class Scene:
    @property
    def path(self) -> Optional[str]: ...
    @property
    def first_prim(self) -> Int64Array: ...
    def pickle_state(self) -> Dict[str, Any]: ...
    @property
    def num_primitives(self) -> int: ...
    @property
    def num_objects(self) -> int: ...
    @property
    def settings(self) -> Dict[str, Any]: ...
    @property
    def warnings(self) -> List[str]: ...
    def triangles(self) -> Float32Array: ...
    def spheres(self) -> Float32Array: ...
    def intersect(
        self,
        origins: Points,
        directions: Points,
        t_min: Bound,
        t_max: Bound,
        *,
        precision: Optional[Precision] = None,
        accel: Accel = "sah",
        threads: Optional[int] = None,
    ) -> _HitColumns: ...
    def occluded(
        self,
        origins: Points,
        directions: Points,
        t_min: Bound,
        t_max: Bound,
        *,
        precision: Optional[Precision] = None,
        accel: Accel = "sah",
        threads: Optional[int] = None,
    ) -> BoolArray: ...
    def intersect_all(
        self,
        origins: Points,
        directions: Points,
        t_min: Bound,
        t_max: Bound,
        *,
        precision: Optional[Precision] = None,
        accel: Accel = "sah",
        threads: Optional[int] = None,
    ) -> _AllHitColumns: ...
    def render(
        self,
        *,
        width: Optional[int] = None,
        height: Optional[int] = None,
        spp: Optional[int] = None,
        max_depth: Optional[int] = None,
        aovs: Sequence[Aov] = ...,
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
        paths: Sequence[Union[str, PathLike[str]]] = ...,
        display_server: Optional[str] = None,
    ) -> _Rendered: ...

@final
class SceneBuilder:
    def __init__(self) -> None: ...
    def add_mesh(
        self, *, vertices: Points, faces: npt.NDArray[Any], name: Optional[str] = None
    ) -> Tuple[int, int]: ...
    def add_sphere(
        self, *, center: Float64Array, radius: float, name: Optional[str] = None
    ) -> Tuple[int, int]: ...
    def add_prototype(self, *, vertices: Points, faces: npt.NDArray[Any]) -> int: ...
    def add_instance(
        self, *, prototype: int, matrix: Float64Array, name: Optional[str] = None
    ) -> Tuple[int, int]: ...
    def build(self) -> Scene: ...

def load(
    path: Union[str, PathLike[str]],
    *,
    defines: Sequence[str] = ...,
    gltf_scene: Optional[int] = None,
    camera: Optional[int] = None,
    up: Optional[Up] = None,
    auto_camera: bool = False,
    frame: Optional[int] = None,
    flatten_instances: bool = False,
    expect_files: Optional[Sequence[Tuple[Union[str, PathLike[str]], str]]] = None,
) -> Scene: ...
def contains(
    scene: Scene, points: Points, *, threads: Optional[int] = None
) -> Tuple[BoolArray, BoolArray]: ...
def containment_methods(scene: Scene) -> List[str]: ...
def near_origins(scene: Scene, origins: Points) -> BoolArray: ...
