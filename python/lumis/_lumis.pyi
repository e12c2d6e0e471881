"""Type stubs of the compiled module `lumis._lumis` (use the `lumis` package's API)."""

from os import PathLike
from typing import Any, Dict, List, Optional, Union

import numpy as np

HIT_COLUMNS: int
ALL_HITS_AVAILABLE: bool

class SceneError(ValueError): ...
class RayError(ValueError): ...

_Bound = Union[float, np.ndarray]

class Scene:
    @property
    def path(self) -> str: ...
    @property
    def num_primitives(self) -> int: ...
    @property
    def num_objects(self) -> int: ...
    @property
    def settings(self) -> Dict[str, Any]: ...
    @property
    def warnings(self) -> List[str]: ...
    def triangles(self) -> np.ndarray: ...
    def spheres(self) -> np.ndarray: ...
    def intersect(
        self, origins: np.ndarray, directions: np.ndarray, t_min: _Bound, t_max: _Bound,
        precision: Optional[str] = None, accel: str = "sah", threads: Optional[int] = None,
    ) -> Dict[str, np.ndarray]: ...
    def occluded(
        self, origins: np.ndarray, directions: np.ndarray, t_min: _Bound, t_max: _Bound,
        precision: Optional[str] = None, accel: str = "sah", threads: Optional[int] = None,
    ) -> np.ndarray: ...
    def intersect_all(
        self, origins: np.ndarray, directions: np.ndarray, t_min: _Bound, t_max: _Bound,
        precision: Optional[str] = None, accel: str = "sah", threads: Optional[int] = None,
    ) -> Dict[str, np.ndarray]: ...
    def render(self, *args: Any, **kwargs: Any) -> Dict[str, Any]: ...

def load(
    path: Union[str, PathLike[str]],
    defines: List[str] = ...,
    gltf_scene: Optional[int] = None,
    camera: Optional[int] = None,
    up: Optional[str] = None,
    auto_camera: bool = False,
    frame: Optional[int] = None,
    flatten_instances: bool = False,
) -> Scene: ...
