"""A navigation goal as the simulator's action servers hold it, and a PoseStamped read as one: shared by the
Nav2 servers (``navigation``) and ROS 1 move_base (``navigation_ros1``) without importing each other."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from pmk_nb.wire import yaw_from_quaternion

if TYPE_CHECKING:
    from pmk_nb.sim.actions import GoalRef


@dataclass
class NavGoal:
    """The goal being driven to, and who to tell about it."""

    kind: str  # "ros2" | "ros1" | "topic"
    target: tuple[float, float, float | None]
    via: list[tuple[float, float]] = field(default_factory=list)
    ref: GoalRef | None = None  # ros2
    goal_id: str = ""  # ros1
    started: float = math.nan  # the engine's clock, set when the navigator starts it
    recoveries: int = 0


#: a goal pose read from a PoseStamped: ((x, y, yaw or None), frame), or why it cannot be a goal
ParsedPose = tuple[tuple[float, float, float | None], str] | str


def parse_pose(pose_stamped: Any) -> ParsedPose:
    """(x, y, yaw) and frame of a PoseStamped, or why it cannot be a goal."""
    if not isinstance(pose_stamped, dict):
        return "pose must be a geometry_msgs/PoseStamped object"
    frame = str((pose_stamped.get("header") or {}).get("frame_id", "")).lstrip("/")
    pose = pose_stamped.get("pose") or {}
    pos = pose.get("position") or {}
    try:
        x, y = float(pos.get("x", math.nan)), float(pos.get("y", math.nan))
        yaw = yaw_from_quaternion(pose["orientation"], strict=True) if pose.get("orientation") else None
    except (TypeError, ValueError):
        return "pose has non-numeric fields"
    if not (math.isfinite(x) and math.isfinite(y)):
        return "goal position is not finite"
    return (x, y, yaw), frame
