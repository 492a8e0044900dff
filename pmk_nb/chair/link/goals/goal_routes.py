"""The routes a goal can take (see :mod:`pmk_nb.chair.link.goals.navigate`): Nav2 actions, ROS 1
actionlib, the goal topic, and waypoints sent one leg after another.

Every callback here runs on roslibpy's I/O thread and only updates the handle; the waypoint runner
and the goal-topic poller run on their own small daemon threads, never on the I/O thread.
"""

from __future__ import annotations

import math
import threading
import time
import weakref
from typing import TYPE_CHECKING, Any

import roslibpy
from roslibpy.core import RosTimeoutError
from roslibpy.ros1 import actionlib

from pmk_nb.chair.link.goals.goal import GoalHandle, GoalRoute, GoalStatus, NavigationError
from pmk_nb.chair.link.goals.goal_attach import ActionStatusFollower
from pmk_nb.chair.link.goals.goal_topic import start_topic
from pmk_nb.errors import ChairLinkError
from pmk_nb.wire import (
    ACTIONLIB_ABORTED,
    ACTIONLIB_ACTIVE,
    ACTIONLIB_LOST,
    ACTIONLIB_PENDING,
    ACTIONLIB_PREEMPTED,
    ACTIONLIB_PREEMPTING,
    ACTIONLIB_RECALLED,
    ACTIONLIB_RECALLING,
    ACTIONLIB_REJECTED,
    ACTIONLIB_SUCCEEDED,
    MOVE_BASE,
    NAV2_ACTION,
    STATUS_ABORTED,
    STATUS_CANCELED,
    STATUS_SUCCEEDED,
    make_stamp,
    quaternion_from_yaw,
)

if TYPE_CHECKING:
    from pmk_nb.chair.link.core import LinkCore

Goal3 = tuple[float, float, float]
# action_msgs/GoalStatus -> ours
NAV2_RESULTS = {
    STATUS_SUCCEEDED: GoalStatus.ARRIVED,
    STATUS_CANCELED: GoalStatus.CANCELLED,
    STATUS_ABORTED: GoalStatus.ABORTED,
}
# actionlib_msgs/GoalStatus -> ours
ACTIONLIB = {
    ACTIONLIB_PENDING: GoalStatus.ACCEPTED,
    ACTIONLIB_ACTIVE: GoalStatus.MOVING,
    ACTIONLIB_PREEMPTED: GoalStatus.CANCELLED,
    ACTIONLIB_SUCCEEDED: GoalStatus.ARRIVED,
    ACTIONLIB_ABORTED: GoalStatus.ABORTED,
    ACTIONLIB_REJECTED: GoalStatus.REJECTED,
    ACTIONLIB_PREEMPTING: GoalStatus.MOVING,  # still moving until the server confirms
    ACTIONLIB_RECALLING: GoalStatus.ACCEPTED,
    ACTIONLIB_RECALLED: GoalStatus.CANCELLED,
    ACTIONLIB_LOST: GoalStatus.ABORTED,
}
_ACTIONLIB_CLIENTS: weakref.WeakKeyDictionary[Any, actionlib.ActionClient] = weakref.WeakKeyDictionary()
_CLIENTS_LOCK = threading.Lock()


def pose_stamped(goal: Goal3, frame: str, ros_version: int | None) -> dict[str, Any]:
    header: dict[str, Any] = {"frame_id": frame, "stamp": make_stamp(time.time(), ros_version)}
    if ros_version == 1:
        header["seq"] = 0
    position = {"x": goal[0], "y": goal[1], "z": 0.0}
    return {"header": header, "pose": {"position": position, "orientation": quaternion_from_yaw(goal[2])}}


def through_poses_args(points: list[tuple[float, float]], goal: Goal3, frame: str, link: LinkCore) -> dict[str, Any]:
    legs = _with_headings([(x, y, None) for x, y in points] + [goal])
    return {"poses": [pose_stamped(g, frame, link.ros_version) for g in legs], "behavior_tree": ""}


def start_nav2(ros: roslibpy.Ros, handle: GoalHandle, action: tuple[str, str], args: dict[str, Any]) -> None:
    """Send a Nav2 goal with roslibpy's ROS 2 ActionClient; feedback gives ``distance_remaining``.
    The action's status topic is followed too, for the goal's fate after a link loss."""
    client = roslibpy.ActionClient(ros, action[0], action[1])
    handle.follower = ActionStatusFollower(ros, action[0], clock=handle.clock)
    seen = [0]

    def feedback(values: Any) -> None:
        seen[0] += 1
        left = values.get("distance_remaining") if hasattr(values, "get") else None
        status = GoalStatus.ACCEPTED if seen[0] == 1 else GoalStatus.MOVING
        handle.update(status, float(left) if isinstance(left, int | float) else None)

    def result(res: Any) -> None:
        code = getattr(res["status"], "value", res["status"])
        status = NAV2_RESULTS.get(int(code), GoalStatus.ABORTED)
        handle.update(status, 0.0 if status is GoalStatus.ARRIVED else None, _why(res.get("values"), status))

    def error(res: Any) -> None:  # result: false; rosbridge-server-rs sends it for a canceled goal too
        code = res.get("status") if hasattr(res, "get") else None
        if NAV2_RESULTS.get(int(getattr(code, "value", code) or 0)) is GoalStatus.CANCELLED:
            status = GoalStatus.CANCELLED
        else:  # rs answers a rejected goal with status 6 (aborted): no feedback yet means rejected
            status = GoalStatus.ABORTED if seen[0] else GoalStatus.REJECTED
        handle.update(status, None, _why(res.get("values") if hasattr(res, "get") else res, status))

    handle.follower.mark_sent()
    goal_id = client.send_goal(roslibpy.Goal(args), result, feedback, error)
    handle.cancel_ref = (action[0], goal_id)  # for a cancel over a second connection (side_channel)
    handle.bind_cancel(lambda: client.cancel_goal(goal_id))


def _why(values: Any, status: GoalStatus) -> str:
    text = values.get("error_msg") if isinstance(values, dict) else values
    return f"{status.value}: {text}" if text else status.value


def _actionlib_client(ros: roslibpy.Ros) -> actionlib.ActionClient:
    """One move_base client per connection (its constructor waits up to 3 s for a status message)."""
    with _CLIENTS_LOCK:
        client = _ACTIONLIB_CLIENTS.get(ros)
        if client is None:
            client = actionlib.ActionClient(ros, MOVE_BASE[0], MOVE_BASE[1])
            _ACTIONLIB_CLIENTS[ros] = client
        return client


def start_actionlib(link: LinkCore, handle: GoalHandle, goal: Goal3, frame: str) -> None:
    """Send a move_base goal over actionlib; status events carry the outcome."""
    ros = link.ros
    if ros is None:
        raise NavigationError("not connected", route=MOVE_BASE[0], host=link.host, port=link.port)
    try:
        client = _actionlib_client(ros)
    except RosTimeoutError as err:
        raise NavigationError(
            f"{MOVE_BASE[0]} sent no status within 3 s", route=MOVE_BASE[0], host=link.host, port=link.port
        ) from err
    message = roslibpy.Message({"target_pose": pose_stamped(goal, frame, 1)})
    sent = actionlib.Goal(client, message)

    def on_status(entry: Any) -> None:
        status = ACTIONLIB.get(int(entry.get("status", 0)), GoalStatus.MOVING)
        text = entry.get("text") or ""
        handle.update(
            status, 0.0 if status is GoalStatus.ARRIVED else None, f"{status.value}: {text}" if text else status.value
        )

    def on_feedback(fb: Any) -> None:
        pos = ((fb.get("base_position") or {}).get("pose") or {}).get("position") or {}
        if "x" in pos and "y" in pos:
            handle.update(GoalStatus.MOVING, math.dist((pos["x"], pos["y"]), goal[:2]))

    sent.on("status", on_status)
    sent.on("feedback", on_feedback)
    sent.send()
    handle.update(GoalStatus.PENDING)
    handle.bind_cancel(sent.cancel)


def start_leg(link: LinkCore, route: GoalRoute, handle: GoalHandle, goal: Goal3, frame: str) -> None:
    ros = link.ros
    if ros is None:
        raise NavigationError("not connected", route=route.name, host=link.host, port=link.port)
    if route.kind == "nav2":
        start_nav2(ros, handle, NAV2_ACTION, {"pose": pose_stamped(goal, frame, 2), "behavior_tree": ""})
    elif route.kind == "actionlib":
        start_actionlib(link, handle, goal, frame)
    else:
        start_topic(link, handle, goal, frame)


def _with_headings(legs: list[tuple[float, float, float | None]]) -> list[Goal3]:
    """Waypoints face the next point; the goal keeps its own heading."""
    out: list[Goal3] = []
    for i, (x, y, yaw) in enumerate(legs):
        if yaw is None:
            nx, ny = legs[i + 1][:2] if i + 1 < len(legs) else (x + 1.0, y)
            yaw = math.atan2(ny - y, nx - x)
        out.append((x, y, yaw))
    return out


def start_legs(
    link: LinkCore, route: GoalRoute, parent: GoalHandle, legs: list[tuple[float, float, float | None]], frame: str
) -> None:
    """Waypoints one after another, on a daemon thread: each leg must arrive before the next."""
    goals = _with_headings(legs)
    parent.route = f"{route.label}, {len(goals) - 1} waypoint(s) one by one"
    parent.update(text="sent")
    threading.Thread(
        target=_run_legs, args=(link, route, parent, goals, frame), daemon=True, name="pmk-goal-legs"
    ).start()


def _run_legs(link: LinkCore, route: GoalRoute, parent: GoalHandle, goals: list[Goal3], frame: str) -> None:
    for i, goal in enumerate(goals):
        if parent.cancel_requested:
            parent.update(GoalStatus.CANCELLED, text="cancelled before the next waypoint")
            return
        rest = sum(math.dist(a[:2], b[:2]) for a, b in zip(goals[i:], goals[i + 1 :], strict=False))
        child = GoalHandle(goal, route.label)

        def forward(p: Any, rest: float = rest) -> None:
            if not p.done:
                parent.update(p.status, None if p.remaining_m is None else p.remaining_m + rest)

        child.on_update(forward)
        try:
            start_leg(link, route, child, goal, frame)
        except ChairLinkError as err:
            parent.update(GoalStatus.ABORTED, text=f"leg {i + 1}/{len(goals)}: {err}")
            return
        parent.bind_cancel(child.cancel)
        while not child.wait(0.2).done:
            pass
        last = child.progress()
        if last.status is not GoalStatus.ARRIVED:
            parent.update(last.status, text=f"leg {i + 1}/{len(goals)}: {last.message}")
            return
    parent.update(GoalStatus.ARRIVED, 0.0)
