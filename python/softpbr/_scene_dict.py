"""A dict with the scene-file schema → the JSON text the scene-file parser reads.

JSON has no NaN or infinity, so a non-finite float (or a value JSON cannot hold) is refused
here with the same kind of message the parser gives, naming the value's JSON pointer:
"<dict>: /lights/0/intensity: expected a finite number, got nan". numpy arrays and scalars
are accepted as lists and numbers.
"""

from __future__ import annotations

import json
import math
from typing import Any, Mapping


def _pointer_token(key: Any) -> str:
    return str(key).replace("~", "~0").replace("/", "~1")


def _plain(value: Any, pointer: str, name: str) -> Any:
    """value with numpy arrays and scalars made lists and numbers, checked for JSON."""
    if hasattr(value, "tolist") and callable(value.tolist):  # numpy arrays and scalars
        value = value.tolist()
    if isinstance(value, bool) or value is None or isinstance(value, (str, int)):
        return value
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"{name}: {pointer or '/'}: expected a finite number, got {value}")
        return value
    if isinstance(value, Mapping):
        out = {}
        for k, v in value.items():
            if not isinstance(k, str):
                raise ValueError(f"{name}: {pointer or '/'}: keys must be strings, got {k!r}")
            out[k] = _plain(v, f"{pointer}/{_pointer_token(k)}", name)
        return out
    if isinstance(value, (list, tuple)):
        return [_plain(v, f"{pointer}/{i}", name) for i, v in enumerate(value)]
    raise ValueError(f"{name}: {pointer or '/'}: expected a JSON value (dict, list, str, number, bool, None), "
                     f"got {type(value).__name__}")


def scene_json(scene: Mapping[str, Any], name: str = "<dict>") -> str:
    if not isinstance(scene, Mapping):
        raise TypeError(f"scene: expected a dict, got {type(scene).__name__}")
    # Floats are written as repr() does (the shortest text that reads back as the same
    # double), so the parser sees the same numbers as in a file written by hand.
    return json.dumps(_plain(scene, "", name), allow_nan=False)
