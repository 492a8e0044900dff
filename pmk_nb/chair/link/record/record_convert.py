"""rosbridge JSON -> the ROS 2 message a recording writes, field by field from its definition (bundled or
described by the bridge, :mod:`.msgdetails`).

Pure functions, no I/O (the recording's writer thread calls them). What differs on the wire from
the ROS 2 message a ``ros2 bag`` holds:

* ROS 1 bridges spell stamps and durations ``secs``/``nsecs``; ROS 2 ``sec``/``nanosec``.
* rosbridge sends NaN, +inf and -inf as JSON ``null``: a float ``null`` becomes NaN (never 0, which
  a laser range would read as an obstacle at the sensor).
* ``uint8[]`` arrives base64-encoded; ROS 1 headers carry ``seq`` (dropped: ROS 2 has none).
* A field the message lacks gets the encoder's default (0, "", empty array).
"""

from __future__ import annotations

import base64
import math
from dataclasses import dataclass
from functools import cache
from typing import Any

from pmk_nb.chair.link.record.msgdefs import DEFINITIONS

FLOATS = frozenset({"float32", "float64"})
BYTES = frozenset({"uint8", "byte", "char"})
PRIMITIVES = FLOATS | BYTES | {"bool", "int8", "int16", "uint16", "int32", "uint32", "int64", "uint64", "string"}
STAMPS = frozenset({"builtin_interfaces/Time", "builtin_interfaces/Duration"})
NS = 1_000_000_000


@dataclass(frozen=True)
class Field:
    """One field of a message definition: ``base`` is a primitive or ``pkg/Type``."""

    name: str
    base: str
    array: bool


def _field(line: str, package: str) -> Field | None:
    """A definition line -> Field; None for blank lines, comments and constants."""
    text = line.split("#", 1)[0].strip()
    parts = text.split()
    if len(parts) < 2 or "=" in parts[1] or (len(parts) > 2 and parts[2].startswith("=")):
        return None
    type_text, name = parts[0], parts[1]
    array = "[" in type_text
    base = type_text.split("[", 1)[0].split("<=", 1)[0]
    if base not in PRIMITIVES and "/" not in base:
        base = "std_msgs/Header" if base == "Header" else f"{package}/{base}"
    return Field(name, base.replace("/msg/", "/"), array)


def parse_definition(type_name: str, text: str) -> dict[str, tuple[Field, ...]]:
    """A concatenated definition (``MSG:`` sections split by ``===`` lines) -> fields per type
    (keys spelled ``pkg/Type``)."""
    found: dict[str, tuple[Field, ...]] = {}
    current = type_name.replace("/msg/", "/")
    lines: list[str] = []

    def close() -> None:
        package = current.split("/", 1)[0]
        found[current] = tuple(f for f in (_field(line, package) for line in lines) if f is not None)

    for line in text.splitlines():
        if line.startswith("==="):
            close()
            lines = []
        elif line.startswith("MSG:"):
            current = line.split(None, 1)[1].strip().replace("/msg/", "/")
        else:
            lines.append(line)
    close()
    return found


@cache
def fields_of(type_name: str, definition: str | None = None) -> dict[str, tuple[Field, ...]]:
    """The parsed definition of ``type_name`` (ROS 2 spelling, ``pkg/msg/Type``): ``definition`` (the
    concatenated text a bridge described), else the bundled one."""
    return parse_definition(type_name, DEFINITIONS[type_name] if definition is None else definition)


def _float(value: Any) -> float:
    return math.nan if value is None else float(value)


def _stamp(value: Any) -> dict[str, int]:
    """A Time or Duration in either spelling -> ``{"sec", "nanosec"}``."""
    value = value if isinstance(value, dict) else {}
    sec = value.get("sec", value.get("secs", 0))
    nanosec = value.get("nanosec", value.get("nsecs", 0))
    return {"sec": int(sec or 0), "nanosec": int(nanosec or 0)}


def _value(field: Field, value: Any, types: dict[str, tuple[Field, ...]]) -> Any:
    if value is None and field.base not in FLOATS:
        return None  # the encoder's default (0, "", [])
    if field.base in STAMPS:
        return [_stamp(v) for v in value] if field.array else _stamp(value)
    if field.base in types:
        return [_message(v, field.base, types) for v in value] if field.array else _message(value, field.base, types)
    if field.base in FLOATS:
        return [_float(v) for v in value or ()] if field.array else _float(value)
    if field.array and field.base in BYTES and isinstance(value, str):
        return base64.b64decode(value)  # rosbridge's uint8[] spelling
    return value


def _message(msg: Any, type_key: str, types: dict[str, tuple[Field, ...]]) -> dict[str, Any]:
    msg = msg if isinstance(msg, dict) else {}
    return {f.name: _value(f, msg.get(f.name), types) for f in types[type_key]}


def to_ros2(msg: dict[str, Any], type_name: str, definition: str | None = None) -> dict[str, Any]:
    """``msg`` as rosbridge sent it (ROS 1 or 2) -> the ROS 2 message of ``type_name`` (``pkg/msg/Type``),
    field by field from ``definition`` (default: the bundled one).

    Raises:
        KeyError: no ``definition`` given and ``type_name`` has no bundled one.
    """
    types = fields_of(type_name, definition)
    return _message(msg, type_name.replace("/msg/", "/"), types)


def stamp_ns(message: dict[str, Any]) -> int | None:
    """A converted message's time (its header stamp, or a TFMessage's first transform's), in ns;
    None when it has none or it is zero."""
    header = message.get("header")
    if header is None and message.get("transforms"):
        header = (message["transforms"][0] or {}).get("header")
    stamp = (header or {}).get("stamp")
    if not stamp:
        return None
    ns = stamp["sec"] * NS + stamp["nanosec"]
    return ns if ns > 0 else None
