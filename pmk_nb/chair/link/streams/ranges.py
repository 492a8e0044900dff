"""Laser ranges read by REP 117, with JSON's ``null`` kept apart as "unknown".

REP 117 gives every LaserScan reading one meaning: a finite value in ``[range_min, range_max]``
is a hit; ``+inf`` is "nothing within range" (free up to ``range_max``); ``-inf`` is "something
closer than ``range_min``"; ``NaN`` is an invalid reading; a finite value outside the limits is
invalid too. rosbridge carries JSON, and JSON has no NaN or Infinity: both the ROS 1 bridge
(rosbridge_suite) and the ROS 2 bridges send all three as ``null``. A ``null`` therefore cannot be
told apart and is **unknown**: never drawn as free floor, because on a wheelchair display "free"
where the sensor is blind, or where something touches the chair, is the wrong way round. Where
the bridge keeps the floats (CBOR, or a JSON decoder that accepts ``Infinity``/``NaN`` tokens,
which Python's does), the three cases are used as REP 117 says.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = [
    "HIT",
    "INVALID",
    "NO_RETURN",
    "TOO_CLOSE",
    "UNKNOWN",
    "BlindSector",
    "blind_ahead",
    "classify_ranges",
]

#: A reading inside [range_min, range_max]: an obstacle at that range.
HIT = 0
#: ``+inf``: nothing within range_max; the ray is free up to range_max.
NO_RETURN = 1
#: ``-inf``: an object closer than range_min (touching the chair).
TOO_CLOSE = 2
#: ``NaN``, or a finite reading outside [range_min, range_max]: the sensor says it is invalid.
INVALID = 3
#: ``null`` on the wire: NaN, +inf or -inf, nobody can tell which.
UNKNOWN = 4

#: Kinds that say nothing about the world (the sensor is blind along that ray).
BLIND_KINDS = (INVALID, UNKNOWN)


def classify_ranges(
    raw: Sequence[Any] | np.ndarray | None, range_min: float, range_max: float
) -> tuple[np.ndarray, np.ndarray]:
    """(ranges float32 with NaN where there is no hit, kinds uint8 per ray) from a scan's ``ranges``.

    ``raw`` is the JSON list (``None`` for null) or an array of floats (CBOR, simulator).
    """
    if raw is None:
        return np.empty(0, np.float32), np.empty(0, np.uint8)
    if isinstance(raw, np.ndarray):
        values = raw.astype(np.float64, copy=False).ravel()
        nulls = np.zeros(values.size, dtype=bool)
    else:
        items = raw if isinstance(raw, list) else list(raw)
        values = _floats(items)
        nulls = np.zeros(values.size, dtype=bool)
        for i in np.flatnonzero(np.isnan(values)):  # only a NaN can have been a null: no loop over hits
            nulls[i] = items[i] is None
    lo = range_min if math.isfinite(range_min) else 0.0
    hi = range_max if not math.isnan(range_max) else math.inf
    kinds = np.full(values.size, INVALID, dtype=np.uint8)
    with np.errstate(invalid="ignore"):
        hit = np.isfinite(values) & (values >= lo) & (values <= hi)
    kinds[hit] = HIT
    kinds[np.isposinf(values)] = NO_RETURN
    kinds[np.isneginf(values)] = TOO_CLOSE
    kinds[nulls] = UNKNOWN
    ranges = np.where(hit, values, np.nan).astype(np.float32)
    return ranges, kinds


def _floats(items: list[Any]) -> np.ndarray:
    """The readings as float64, None -> NaN; NumPy converts a whole list at once (a scan is parsed on
    the link's I/O thread, per message), ray by ray only when something is not a number."""
    try:
        values = np.array(items, dtype=np.float64)
        if values.ndim == 1:
            return values
    except (TypeError, ValueError):
        pass
    return np.array([math.nan if v is None else _number(v) for v in items], dtype=np.float64)


def _number(value: Any) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        return math.nan  # a string or object where a float belongs is an invalid reading


@dataclass(frozen=True)
class BlindSector:
    """The widest run of blind rays across the chair's heading.

    Attributes:
        degrees: angular width of the run.
        rays: how many rays it holds.
        too_close: rays in the forward window that say "object closer than range_min".
    """

    degrees: float
    rays: int
    too_close: int


def blind_ahead(
    kinds: np.ndarray,
    angles: np.ndarray,
    *,
    heading_offset: float = 0.0,
    window: float = math.radians(30.0),
) -> BlindSector:
    """The widest contiguous run of blind rays (unknown or invalid) that reaches into ``±window``.

    ``angles`` are the rays' directions in the laser frame; ``heading_offset`` is the chair's
    forward direction in that frame (the laser's mounting yaw, negated). A run counts when any of
    its rays points within ``window`` of straight ahead; its full width is reported, so a
    90° blind sector that starts 10° right of ahead reads as 90°, not 10°.
    """
    k = np.asarray(kinds).ravel()
    a = np.asarray(angles, dtype=np.float64).ravel()[: k.size]
    if k.size == 0 or a.size != k.size:
        return BlindSector(0.0, 0, 0)
    rel = np.angle(np.exp(1j * (a - heading_offset)))
    ahead = np.abs(rel) <= window
    close = int(np.count_nonzero(ahead & (k == TOO_CLOSE)))
    blind = np.isin(k, BLIND_KINDS)
    # runs of blind rays as [start, end) index pairs, found with one diff instead of a loop per ray
    edges = np.flatnonzero(np.diff(np.concatenate(([0], blind.astype(np.int8), [0]))))
    starts, ends = edges[::2], edges[1::2]
    ahead_sum = np.concatenate(([0], np.cumsum(ahead)))
    counted = ahead_sum[ends] - ahead_sum[starts] > 0  # the run has a ray within the window
    if not counted.any():
        return BlindSector(0.0, 0, close)
    lengths = np.where(counted, ends - starts, 0)
    i = int(np.argmax(lengths))  # the first of the widest, as before
    first, last = int(starts[i]), int(ends[i]) - 1
    width = abs(math.degrees(a[last] - a[first])) + abs(math.degrees(_step(a)))
    return BlindSector(round(width, 1), int(lengths[i]), close)


def _step(angles: np.ndarray) -> float:
    return float(angles[1] - angles[0]) if angles.size > 1 else 0.0
