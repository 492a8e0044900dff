"""ROS 1 ``move_base`` over actionlib topics, the way actionlib's action server speaks them.

In: ``/move_base/goal`` (``move_base_msgs/MoveBaseActionGoal``), ``/move_base/cancel``
(``actionlib_msgs/GoalID``: an id, or an empty id for "all goals"). Out: ``/move_base/status``
(``actionlib_msgs/GoalStatusArray``, published continuously, as actionlib does: clients such as
roslibpy wait for it before sending), ``/move_base/feedback`` (``base_position``) and
``/move_base/result``. Finished goals stay in the status list for a few seconds.
"""

from __future__ import annotations

import itertools
from typing import TYPE_CHECKING, Any, TypedDict

from pmk_nb.sim.navgoal import NavGoal, parse_pose
from pmk_nb.wire import ACTIONLIB_ABORTED as ABORTED
from pmk_nb.wire import ACTIONLIB_ACTIVE as ACTIVE
from pmk_nb.wire import ACTIONLIB_PREEMPTED as PREEMPTED
from pmk_nb.wire import ACTIONLIB_REJECTED as REJECTED
from pmk_nb.wire import ACTIONLIB_SUCCEEDED as SUCCEEDED
from pmk_nb.wire import MOVE_BASE, pose_msg

if TYPE_CHECKING:
    from pmk_nb.sim.messages import Names
    from pmk_nb.sim.navroles import GoalKeeper
    from pmk_nb.sim.protocol import Bridge

# actionlib_msgs/GoalStatus
CODES = {"succeeded": SUCCEEDED, "aborted": ABORTED, "canceled": PREEMPTED}
KEEP_DONE_S = 5.0  # how long a finished goal stays in the status list
SERVER = MOVE_BASE[0]
_IDS = itertools.count(1)  # a goal sent without an id gets one


class GoalID(TypedDict):
    """actionlib_msgs/GoalID."""

    stamp: dict[str, int]
    id: str


class GoalStatus(TypedDict):
    """actionlib_msgs/GoalStatus: kept after the goal ends (KEEP_DONE_S) and published in each status array."""

    goal_id: GoalID
    status: int
    text: str


class Ros1Actionlib:
    """The move_base action server's topics on one bridge, on the engine's clocks (``nav.engine``)."""

    def __init__(self, nav: GoalKeeper, bridge: Bridge, names: Names) -> None:
        self.nav, self.bridge, self.names = nav, bridge, names
        self.clock, self.wall = nav.engine.clock, nav.engine.wall
        self._done: list[tuple[float, GoalStatus]] = []  # (time finished, status entry)
        bridge.advertise_internal(f"{SERVER}/status", "actionlib_msgs/GoalStatusArray")
        bridge.advertise_internal(f"{SERVER}/feedback", "move_base_msgs/MoveBaseActionFeedback")
        bridge.advertise_internal(f"{SERVER}/result", "move_base_msgs/MoveBaseActionResult")
        bridge.listen(f"{SERVER}/goal", "move_base_msgs/MoveBaseActionGoal", self.on_goal)
        bridge.listen(f"{SERVER}/cancel", "actionlib_msgs/GoalID", self.on_cancel)

    def _entry(self, goal_id: str, status: int, text: str = "") -> GoalStatus:
        return {"goal_id": {"stamp": self.names.stamp(0.0), "id": goal_id}, "status": status, "text": text}

    def on_goal(self, msg: dict[str, Any]) -> None:
        goal_id = str((msg.get("goal_id") or {}).get("id") or f"sim-goal-{next(_IDS)}")
        parsed = parse_pose((msg.get("goal") or {}).get("target_pose"))
        why = parsed if isinstance(parsed, str) else self.nav.check(*parsed)
        if isinstance(parsed, str) or why is not None:
            self._publish_result(self._entry(goal_id, REJECTED, f"goal rejected: {why}"))
            return
        self.nav.start(NavGoal("ros1", parsed[0], goal_id=goal_id))

    def on_cancel(self, msg: dict[str, Any]) -> None:
        goal = self.nav.current
        wanted = str(msg.get("id") or "")
        if goal is not None and goal.kind == "ros1" and wanted in ("", goal.goal_id):
            self.nav.cancel_current("cancelled by the client")

    def feedback(self, goal: NavGoal, pose: tuple[float, float, float]) -> None:
        t = self.wall.now()
        msg = {
            "header": self.names.header("", t),
            "status": self._entry(goal.goal_id, ACTIVE),
            "feedback": {"base_position": {"header": self.names.header("map", t), "pose": pose_msg(*pose)}},
        }
        self.bridge.publish(f"{SERVER}/feedback", msg)

    def result(self, goal: NavGoal, outcome: str, why: str) -> None:
        self._publish_result(self._entry(goal.goal_id, CODES[outcome], "" if outcome == "succeeded" else why))

    def _publish_result(self, entry: GoalStatus) -> None:
        self._done.append((self.clock.now(), entry))
        self.publish_status(self.nav.current)  # the terminal status first, as actionlib does
        msg = {"header": self.names.header("", self.wall.now()), "status": entry, "result": {}}
        self.bridge.publish(f"{SERVER}/result", msg)

    def publish_status(self, goal: NavGoal | None) -> None:
        now = self.clock.now()
        self._done = [(t, e) for t, e in self._done if now - t < KEEP_DONE_S]
        entries = [e for _, e in self._done]
        if goal is not None and goal.kind == "ros1":
            entries.append(self._entry(goal.goal_id, ACTIVE))
        msg = {"header": self.names.header("", self.wall.now()), "status_list": entries}
        self.bridge.publish(f"{SERVER}/status", msg)
