"""`-D KEY=VALUE` strings from Python values (the keyword arguments of `lumis.load`)."""

from __future__ import annotations

import json
import math
import numbers
from typing import Any, Iterable, Mapping, Union

Defines = Union[Mapping[str, Any], Iterable[str], None]


def toml_value(value: Any) -> str:
    """`value` as TOML text: bool, int, float (inf/nan too), str, or a list/tuple of them."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        x = float(value)
        if math.isnan(x):
            return "nan"
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        return repr(x)
    if isinstance(value, str):
        # A TOML basic string: JSON's escapes are TOML's, except DEL, which TOML wants escaped.
        return json.dumps(value, ensure_ascii=False).replace("\x7f", "\\u007f")
    if hasattr(value, "tolist"):  # numpy arrays and scalars
        return toml_value(value.tolist())
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    raise TypeError(
        f"cannot pass {type(value).__name__} {value!r} as a scene parameter "
        "(expected bool, int, float, str or a list of them)"
    )


def define_strings(defines: Defines, overrides: Mapping[str, Any]) -> list[str]:
    """The `KEY=VALUE` strings of `defines` (a dict, or `KEY=VALUE` strings as on the command
    line) then `overrides` (keyword arguments), in that order: a later one wins."""
    out: list[str] = []
    if defines is None:
        pass
    elif isinstance(defines, Mapping):
        out += [f"{k}={toml_value(v)}" for k, v in defines.items()]
    elif isinstance(defines, str):
        out.append(defines)
    else:
        out += [str(d) for d in defines]
    out += [f"{k}={toml_value(v)}" for k, v in overrides.items()]
    return out
