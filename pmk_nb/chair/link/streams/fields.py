"""Any numeric field of any topic (issue 40, Plots): the field paths from the bridge's type definitions,
and a field's value read from a message.

rosapi's ``message_details`` gives a type's definition and its nested types' (``fieldnames``,
``fieldtypes``, ``fieldarraylen``: -1 not an array, 0 variable length, n fixed), so the fields are
known before a message arrives. Numbers, booleans and stamps (``time``, ``builtin_interfaces/Time``: one
value in seconds) are leaves; fixed arrays of numbers (a covariance) give one path per item; variable
arrays (a scan's ranges, a path's poses) are not offered: an item there has no fixed meaning. Without a
definition (a bridge without ``message_details``) the numeric leaves of a message seen stand in.
Paths read ``twist.twist.linear.x``, ``pose.covariance[35]``.
"""

from __future__ import annotations

import math
import re
from typing import Any

from pmk_nb.wire import normalise_type, stamp_to_sec

__all__ = ["MAX_FIELDS", "field_value", "numeric_fields", "sample_fields"]

NUMBERS = {
    "bool", "byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64",
    "float32", "float64", "float", "double",
}  # fmt: skip
STAMPS = {"time", "duration", "builtin_interfaces/Time", "builtin_interfaces/Duration"}
MAX_FIELDS = 400  # a picker longer than this helps no one (and bounds a recursive definition)
MAX_DEPTH = 12
_INDEX = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)(?:\[(\d+)\])?$")


def numeric_fields(typedefs: list[dict[str, Any]], root: str) -> list[str]:
    """The numeric field paths of ``root`` by its definitions, in definition order."""
    defs = {normalise_type(str(d.get("type", ""))): d for d in typedefs if isinstance(d, dict)}
    out: list[str] = []

    def walk(type_name: str, prefix: str, depth: int) -> None:
        d = defs.get(normalise_type(type_name))
        if d is None or depth > MAX_DEPTH:
            return
        names, types = list(d.get("fieldnames") or []), list(d.get("fieldtypes") or [])
        lengths = list(d.get("fieldarraylen") or [-1] * len(names))
        for name, ftype, length in zip(names, types, lengths, strict=False):
            if len(out) >= MAX_FIELDS:
                return
            path, base = f"{prefix}{name}", str(ftype)
            leaf = base in NUMBERS or base in STAMPS or normalise_type(base) in STAMPS
            if length == 0:
                continue  # variable length: no item has a fixed meaning
            if length > 0:
                if leaf:
                    out.extend(f"{path}[{i}]" for i in range(min(length, MAX_FIELDS - len(out))))
                continue
            if leaf:
                out.append(path)
            else:
                walk(base, f"{path}.", depth + 1)

    walk(root, "", 0)
    return out


def sample_fields(msg: Any, prefix: str = "", depth: int = 0, limit: int = 36) -> list[str]:
    """The numeric leaves of a message seen (no definition to go by); lists up to ``limit`` items."""
    out: list[str] = []
    if depth > MAX_DEPTH:
        return out
    if isinstance(msg, dict):
        if stamp_to_sec(msg) is not None and prefix:
            return [prefix.rstrip(".")]
        for key, value in msg.items():
            out += sample_fields(value, f"{prefix}{key}.", depth + 1, limit)
    elif isinstance(msg, list) and 0 < len(msg) <= limit and all(_is_number(v) for v in msg):
        out += [f"{prefix.rstrip('.')}[{i}]" for i in range(len(msg))]
    elif _is_number(msg) and prefix:
        out.append(prefix.rstrip("."))
    return out[:MAX_FIELDS]


def _is_number(value: Any) -> bool:
    return isinstance(value, int | float)


def field_value(msg: Any, path: str) -> float | None:
    """The value at ``path`` as a float (booleans 0/1, stamps in seconds); None when the message has
    no such field or it is not a number (JSON null: NaN and infinities as rosbridge sends them)."""
    value = msg
    for part in path.split("."):
        m = _INDEX.match(part)
        if m is None or not isinstance(value, dict) or m.group(1) not in value:
            return None
        value = value[m.group(1)]
        if m.group(2) is not None:
            i = int(m.group(2))
            if not isinstance(value, list) or i >= len(value):
                return None
            value = value[i]
    if isinstance(value, dict):
        return stamp_to_sec(value)
    if isinstance(value, bool):
        return float(value)
    if isinstance(value, int | float) and math.isfinite(value):
        return float(value)
    return None
