"""Planar angles as the wire carries them: a yaw wrapped to (-pi, pi], and the quaternion a
``geometry_msgs/Quaternion`` spells it with (rotation about z only: a wheelchair moves in the plane).

The link reads these from rosbridge JSON, the simulator writes them, the live view composes poses
with them: one spelling, so a pose the simulator sends is the pose the dashboard reads.
"""

from __future__ import annotations

import math
from typing import Any


def wrap_angle(a: float) -> float:
    """Angle in (-pi, pi]."""
    a = math.fmod(a + math.pi, 2.0 * math.pi)
    if a <= 0.0:
        a += 2.0 * math.pi
    return a - math.pi


def yaw_from_quaternion(q: dict[str, Any] | None, *, strict: bool = False) -> float:
    """Heading (rotation about z) of a ``geometry_msgs/Quaternion`` dict, in (-pi, pi].

    Missing fields read as the identity's (x = y = z = 0, w = 1). Reading what a chair sent, a JSON
    ``null`` field (rosbridge's NaN) and a missing dict do too; ``strict`` (a goal a client sent, which
    rosbridge would refuse) lets ``float`` raise on a ``null`` or non-numeric field instead.
    """
    if not q:
        return 0.0
    if strict:
        x, y = float(q.get("x", 0.0)), float(q.get("y", 0.0))
        z, w = float(q.get("z", 0.0)), float(q.get("w", 1.0))
    else:
        x, y = float(q.get("x") or 0.0), float(q.get("y") or 0.0)
        z, w = float(q.get("z") or 0.0), float(q.get("w", 1.0) if q.get("w") is not None else 1.0)
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def quaternion_from_yaw(theta: float) -> dict[str, float]:
    """The ``geometry_msgs/Quaternion`` dict of a rotation by ``theta`` about z."""
    return {"x": 0.0, "y": 0.0, "z": math.sin(theta / 2.0), "w": math.cos(theta / 2.0)}
