"""A decoded message -> one flat table row: the pure core of :mod:`.read` (no I/O, no pandas).

Whatever decoded it (mcap_ros2's objects, rosbags' dataclasses, JSON dicts), a message becomes a dict
of dotted column names, as a researcher writes them:

* nested messages are spelled out: ``pose.pose.position.x``;
* a sequence of numbers stays in one cell as a numpy array (``ranges``, ``covariance``; stack them
  with ``np.stack(frame["ranges"])``): one column per ray would give a scan 720 columns;
* a sequence of messages stays in one cell as a list of flattened dicts (``transforms``, ``poses``,
  ``markers``): its length changes from message to message, so fixed columns could not hold it;
* ``uint8[]`` / ``byte[]`` stay ``bytes`` (or a uint8 array, as the decoder gives them), strings stay strings.

Each row starts with ``received`` (the MCAP ``log_time``: when the recorder got it, in seconds since
the epoch) and ``stamp`` (the message's header stamp in seconds; a ``TFMessage``'s first transform's;
NaN when it has none).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

NS = 1e9
TIME_COLUMNS = ("received", "stamp")


def _is_message(value: Any) -> bool:
    return isinstance(value, Mapping) or hasattr(value, "__slots__") or dataclasses.is_dataclass(value)


def _items(message: Any) -> list[tuple[str, Any]]:
    """A message's (field, value) pairs, whatever decoded it (rosbags' ``__msgtype__`` is no field)."""
    if isinstance(message, Mapping):
        return [(str(k), v) for k, v in message.items()]
    if dataclasses.is_dataclass(message):
        names = [f.name for f in dataclasses.fields(message)]
    else:
        names = list(message.__slots__)
    return [(name, getattr(message, name)) for name in names if not name.startswith("__")]


def _sequence(values: Any) -> Any:
    """A sequence field's cell: messages -> list of flat dicts, numbers -> numpy array, else a list."""
    if isinstance(values, bytes | bytearray | np.ndarray):
        return bytes(values) if isinstance(values, bytearray) else values
    items = list(values)
    if items and all(_is_message(v) for v in items):
        return [flatten(v) for v in items]
    if items and all(isinstance(v, bool | int | float) or v is None for v in items):
        return np.asarray([math.nan if v is None else v for v in items])
    return items


def flatten(message: Any, prefix: str = "") -> dict[str, Any]:
    """``message`` -> {dotted field name: value}; see the module's rules for sequences."""
    row: dict[str, Any] = {}
    for name, value in _items(message):
        key = f"{prefix}{name}"
        if _is_message(value):
            row |= flatten(value, key + ".")
        elif isinstance(value, list | tuple | bytes | bytearray | np.ndarray):
            row[key] = _sequence(value)
        elif isinstance(value, np.generic):
            row[key] = value.item()
        else:
            row[key] = value
    return row


def _seconds(stamp: Mapping[str, Any]) -> float:
    """A Time in any spelling (ROS 2 ``sec/nanosec``, ROS 1 ``secs/nsecs``, Foxglove ``sec/nsec``)."""
    sec = stamp.get("sec", stamp.get("secs"))
    nsec = stamp.get("nanosec", stamp.get("nsecs", stamp.get("nsec", 0)))
    if not isinstance(sec, int | float) or not isinstance(nsec, int | float):
        return math.nan
    return float(sec) + float(nsec) / NS


def stamp_seconds(flat: Mapping[str, Any]) -> float:
    """A flat row's header stamp in seconds: ``header.stamp``, else the first of ``transforms``; NaN if none."""
    for prefix in ("header.stamp.", "stamp."):
        stamp = {k.removeprefix(prefix): v for k, v in flat.items() if k.startswith(prefix)}
        if stamp:
            return _seconds(stamp)
    transforms = flat.get("transforms")
    if isinstance(transforms, list) and transforms and isinstance(transforms[0], Mapping):
        return stamp_seconds(transforms[0])
    return math.nan


def row(message: Any, log_time_ns: int) -> dict[str, Any]:
    """One table row: ``received`` and ``stamp`` (seconds), then the message's flattened fields."""
    flat = flatten(message)
    return {"received": log_time_ns / NS, "stamp": stamp_seconds(flat), **flat}
