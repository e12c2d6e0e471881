"""`Scene.contains`: point containment, exact for closed meshes and spheres, by the
generalized winding number for meshes that are not closed (docs/hard-cases.md, "Point
containment")."""

from __future__ import annotations

import warnings
from typing import List, Optional

import numpy as np
import numpy.typing as npt

from . import _lumis
from ._types import BoolArray, Points


class WindingNumberWarning(UserWarning):
    """Some points were answered by the generalized winding number of a mesh that is not
    closed (threshold 1/2): not an exact answer. `Scene.containment_methods` tells which
    objects answer that way."""


def query_points(points: npt.ArrayLike) -> Points:
    """`(N, 3)` points as float32 or float64 (read in place), others converted to float64."""
    a = np.asarray(points)
    if a.dtype == np.float32 or a.dtype == np.float64:
        return a
    return a.astype(np.float64)


def contains(inner: _lumis.Scene, points: npt.ArrayLike, threads: Optional[int]) -> BoolArray:
    """The bool answers; warns once per call when any came from the winding number."""
    inside, winding = _lumis.contains(inner, query_points(points), threads=threads)
    count = int(np.count_nonzero(winding))
    if count:
        methods: List[str] = _lumis.containment_methods(inner)
        open_ids = [i for i, m in enumerate(methods) if m == "winding_number"]
        warnings.warn(
            f"{count} of {len(inside)} points were answered by the generalized winding "
            f"number (threshold 1/2) of objects that are not closed (obj_id {open_ids}): "
            "not exact; see docs/hard-cases.md, \"Point containment\"",
            WindingNumberWarning,
            stacklevel=3,
        )
    return inside
