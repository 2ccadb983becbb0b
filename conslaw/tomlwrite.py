"""A small TOML writer for resolved scene files (the standard library only reads TOML)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any


def _scalar(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        escaped = value.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")
        return f'"{escaped}"'
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_scalar(v) for v in value) + "]"
    if isinstance(value, Mapping):
        return "{ " + ", ".join(f"{_key(k)} = {_scalar(v)}" for k, v in value.items()) + " }"
    raise TypeError(f"cannot write {type(value).__name__} to TOML")


def _key(key: str) -> str:
    if key and all(c.isalnum() or c in "-_" for c in key):
        return key
    return _scalar(key)


def dumps(document: Mapping[str, Any]) -> str:
    """TOML text of a mapping: scalars first, then one ``[table]`` per nested mapping."""
    lines = [f"{_key(k)} = {_scalar(v)}" for k, v in document.items() if not isinstance(v, Mapping)]
    for key, value in document.items():
        if isinstance(value, Mapping):
            lines.append("")
            lines.append(f"[{_key(key)}]")
            lines.extend(f"{_key(k)} = {_scalar(v)}" for k, v in value.items())
    return "\n".join(lines) + "\n"
