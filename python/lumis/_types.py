"""The names the options take, as `Literal` types (re-exported by `lumis`), and the array
types of the API. The compiled module lists the names it accepts in `lumis._lumis.CHOICES`
(from the library's own types); tests/test_typing.py checks that these agree."""

from __future__ import annotations

from typing import Literal, Union

import numpy as np
import numpy.typing as npt

#: The accelerators (`lumis hits --accel`).
Accel = Literal["sah", "brute", "bsp", "bsmp"]
#: The primitive tests (`lumis hits --precision`).
Precision = Literal["watertight", "fast", "double"]
#: The model axis that points up (`lumis render --up`; upper case is accepted too).
Up = Literal["y", "z"]
#: The EXR's channel names (`lumis render --layout`).
Layout = Literal["lumis", "blender"]
#: The PNG's tone curve (`lumis render --tonemap`).
Tonemap = Literal["none", "filmic"]
#: The PNG's display transform (`lumis render --display`).
Display = Literal["srgb", "clamp"]
#: The extra layers of a render (`lumis render --aov`).
Aov = Literal["albedo", "position", "uv", "lightpaths", "lights", "samples"]

Float32Array = npt.NDArray[np.float32]
Float64Array = npt.NDArray[np.float64]
Int64Array = npt.NDArray[np.int64]
BoolArray = npt.NDArray[np.bool_]
#: A float32 or float64 array: what the compiled module reads in place.
Points = Union[Float32Array, Float64Array]
#: `t_min`, `t_max` as the compiled module takes them: a number, or one per ray.
Bound = Union[float, Float32Array, Float64Array]
