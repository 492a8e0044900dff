"""Navigation goals as a chair's navigation stack offers them, over the simulator's own planner.

ROS 2 flavour: Nav2's ``/navigate_to_pose`` (``nav2_msgs/action/NavigateToPose``) and
``/navigate_through_poses`` actions over the rosbridge action ops, plus the ``/goal_pose`` topic.
ROS 1 flavour: ``move_base`` over actionlib topics (``/move_base/goal``, ``/cancel``, ``/status``,
``/feedback``, ``/result``), plus ``/move_base_simple/goal``. One goal at a time: a new goal (from
any of these) preempts the running one. A ``/cmd_vel`` command from elsewhere does not cancel it:
Nav2's and move_base's controllers keep publishing, so only a cancel (the action's, move_base's
``/cancel`` or Nav2's ``_action/cancel_goal`` service with a zero id: all goals) ends it. A chair
with goal topics only (``offer_actions`` False: a simple goal follower) yields to ``/cmd_vel``. Feedback (distance
remaining along the planned path) goes out at ``FEEDBACK_HZ``. Goals off the map, in another frame
or not finite are rejected; goals the planner cannot reach are accepted, then aborted, as Nav2 does.
"""

from __future__ import annotations

import asyncio
import itertools
import math
from typing import TYPE_CHECKING, Any

from pmk_nb.clock import AsyncPacer
from pmk_nb.sim import actions as a2
from pmk_nb.sim.action_status import ActionStatus
from pmk_nb.sim.actions import GoalRef
from pmk_nb.sim.cancel_service import add_cancel_services
from pmk_nb.sim.navgoal import NavGoal, ParsedPose, parse_pose
from pmk_nb.sim.navigation_ros1 import Ros1Actionlib
from pmk_nb.wire import NAV2_ACTION, NAV2_ACTIONS, NAV2_THROUGH, make_stamp, pose_msg

if TYPE_CHECKING:
    from pmk_nb.sim.navroles import PlanningEngine
    from pmk_nb.sim.protocol import Bridge
    from pmk_nb.sim.session import ClientSession

FEEDBACK_HZ = 5.0
FRAMES = ("map", "odom", "")
# the chair's goal_status -> outcome name
_OUTCOMES = {"reached": "succeeded", "blocked": "aborted", "no_path": "aborted", "cancelled": "canceled"}
_ROS2_CODES = {"succeeded": a2.STATUS_SUCCEEDED, "aborted": a2.STATUS_ABORTED, "canceled": a2.STATUS_CANCELED}
_ERROR_CODES = {"succeeded": 0, "aborted": 204, "canceled": 0}  # Nav2 Jazzy: 204 = no valid path / failed


class Navigator:
    """Goal bookkeeping on the simulator's loop; the engine plans and drives."""

    def __init__(self, engine: PlanningEngine) -> None:
        self.engine = engine
        self.current: NavGoal | None = None
        self.ros1: Ros1Actionlib | None = None
        self.bridge: Bridge | None = None
        self.offer_actions = True  # False: a chair with goal topics only (no move_base / Nav2 actions)
        self.status: ActionStatus | None = None  # ROS 2: the actions' _action/status topics

    def attach(self, bridge: Bridge) -> None:
        self.bridge = bridge
        n = self.engine.names
        if self.offer_actions and n.ros == "ros2":
            bridge.add_action(*NAV2_ACTION, _ToPose(self))
            bridge.add_action(*NAV2_THROUGH, _ThroughPoses(self))
            self.status = ActionStatus(bridge, n, NAV2_ACTIONS, clock=self.engine.clock, wall=self.engine.wall)
            add_cancel_services(self, NAV2_ACTIONS)
        elif self.offer_actions:
            self.ros1 = Ros1Actionlib(self, bridge, n)
        if n.ros == "ros2":
            bridge.listen("/goal_pose", n.msg("geometry_msgs", "PoseStamped"), self.on_topic_goal)
        bridge.listen("/move_base_simple/goal", n.msg("geometry_msgs", "PoseStamped"), self.on_topic_goal)

    @property
    def bridge_is_rs(self) -> bool:
        return self.bridge is not None and self.bridge.mode == "rs"

    def task(self) -> asyncio.Task[None]:
        return asyncio.create_task(self._loop())

    # -- inputs -----------------------------------------------------------------------------------

    def check(self, target: tuple[float, float, float | None], frame: str) -> str | None:
        """Why a goal is rejected, or None."""
        world = self.engine.world
        if frame not in FRAMES:
            return f"frame '{frame}' is not known (use map)"
        if world is None or self.engine.chair is None:
            return "no map loaded"
        grid = world.grid
        col, row = grid.world_to_cell(target[0], target[1])
        if not (0 <= col < grid.width and 0 <= row < grid.height):
            return f"goal ({target[0]:.2f}, {target[1]:.2f}) is outside the map"
        return None

    def start(self, goal: NavGoal) -> None:
        """Preempt the running goal and plan to the new one."""
        if self.current is not None:
            self.finish("canceled", "preempted by a new goal")
        self.current = goal
        goal.started = self.engine.clock.now()
        if goal.ref is not None and self.status is not None:
            self.status.set(goal.ref, a2.STATUS_EXECUTING)
        self.engine.start_plan(goal.target[:2], goal.target[2], via=goal.via)
        self._feedback(goal)

    def on_topic_goal(self, msg: dict[str, Any]) -> None:
        parsed = parse_pose(msg)
        if isinstance(parsed, str) or self.check(*parsed) is not None:
            return
        self.start(NavGoal("topic", parsed[0]))

    def cancel_current(self, why: str = "cancelled") -> None:
        if self.current is None:
            return
        self.engine.cancel_plan()
        if self.engine.chair is not None:
            self.engine.chair.stop_goal()
        self.finish("canceled", why)

    # -- progress ---------------------------------------------------------------------------------

    async def _loop(self) -> None:
        period, pacer = 1.0 / FEEDBACK_HZ, AsyncPacer(self.engine.clock)
        while True:
            await pacer.sleep(period)
            if self.engine.paused:
                continue
            try:
                self.tick()
            except Exception:  # a bug must not end the loop
                self.engine.note("navigation tick failed")

    def tick(self) -> None:
        goal, chair = self.current, self.engine.chair
        if self.ros1 is not None:
            self.ros1.publish_status(goal)
        if goal is None or chair is None:
            return
        status = chair.goal_status
        if status == "planning" and not self.engine.planning:
            self.finish("canceled", "the plan was dropped (manual command or new map)")
        elif status in _OUTCOMES:
            why = {"no_path": "no path to the goal", "blocked": "the chair is blocked"}.get(status, status)
            self.finish(_OUTCOMES[status], why)
        else:
            self._feedback(goal)

    def remaining(self, goal: NavGoal) -> float:
        chair = self.engine.chair
        left = chair.remaining_distance() if chair is not None else None
        if left is None and chair is not None:  # still planning: straight lines through the waypoints
            points = [chair.pose[:2], *goal.via, goal.target[:2]]
            left = sum(math.dist(a, b) for a, b in itertools.pairwise(points))
        return float(left or 0.0)

    def _feedback(self, goal: NavGoal) -> None:
        chair = self.engine.chair
        if chair is None:
            return
        if goal.kind == "ros2" and goal.ref is not None:
            n, t = self.engine.names, self.engine.wall.now()
            left = self.remaining(goal)
            elapsed = self.engine.clock.now() - goal.started
            speed = max(self.engine.limits.v_max * 0.6, 1e-3)
            goal.ref.feedback(
                {
                    "current_pose": {"header": n.header("map", t), "pose": pose_msg(*chair.pose)},
                    "navigation_time": _duration(elapsed),
                    "estimated_time_remaining": _duration(left / speed),
                    "number_of_recoveries": goal.recoveries,
                    "distance_remaining": left,
                }
            )
        elif goal.kind == "ros1" and self.ros1 is not None:
            self.ros1.feedback(goal, chair.pose)

    def finish(self, outcome: str, why: str) -> None:
        """End the current goal: tell its client (succeeded / aborted / canceled)."""
        goal, self.current = self.current, None
        if goal is None:
            return
        self.engine.goal_ended()
        if goal.kind == "ros2" and goal.ref is not None:
            if self.status is not None:
                self.status.set(goal.ref, _ROS2_CODES[outcome])
            values = {"error_code": _ERROR_CODES[outcome], "error_msg": "" if outcome == "succeeded" else why}
            # rosbridge-server-rs 0.1.6 answers a canceled goal with ``result: false`` (measured)
            ok = not (outcome == "canceled" and self.bridge_is_rs)
            goal.ref.result(_ROS2_CODES[outcome], values, ok)
        elif goal.kind == "ros1" and self.ros1 is not None:
            self.ros1.result(goal, outcome, why)
        if outcome != "succeeded":
            self.engine.note(f"goal ({goal.target[0]:.2f}, {goal.target[1]:.2f}) {outcome}: {why}")


class _ToPose:
    """Nav2 NavigateToPose: goal ``{pose: PoseStamped, behavior_tree}``."""

    def __init__(self, nav: Navigator) -> None:
        self.nav = nav

    def goal(self, ref: GoalRef, args: dict[str, Any]) -> None:
        parsed = parse_pose(args.get("pose"))
        self._start(ref, parsed, [])

    def _start(self, ref: GoalRef, parsed: ParsedPose, via: list[tuple[float, float]]) -> None:
        why = parsed if isinstance(parsed, str) else self.nav.check(*parsed)
        if why is not None or isinstance(parsed, str):
            self.nav.engine.note(f"goal rejected: {why}")  # the bridge does not pass the reason on
            ref.reject()
            return
        self.nav.start(NavGoal("ros2", parsed[0], via=via, ref=ref))

    def cancel(self, ref: GoalRef) -> None:
        """rs: the client's own goal. rosbridge_suite keys its running goals by the client's id in a
        class-level dict (``SendActionGoal.client_handler_list``), so any connection can cancel one."""
        goal = self.nav.current
        anyone = self.nav.bridge is not None and self.nav.bridge.bridge_facts.cancel_from_any_client
        mine = goal is not None and goal.ref is not None and (anyone or goal.ref.client is ref.client)
        if mine and goal is not None and goal.ref is not None and goal.ref.goal_id == ref.goal_id:
            self.nav.cancel_current("cancelled by the client")
            return
        ref.client.status("warning", f"cancel_action_goal {ref.action}: no running goal with id {ref.goal_id}")

    def client_gone(self, client: ClientSession) -> None:
        goal = self.nav.current
        if goal is not None and goal.ref is not None and goal.ref.client is client:
            self.nav.cancel_current("the client disconnected")  # only in bridge mode rs (see bridge_modes)


class _ThroughPoses(_ToPose):
    """Nav2 NavigateThroughPoses: goal ``{poses: PoseStamped[], behavior_tree}``, driven in order."""

    def goal(self, ref: GoalRef, args: dict[str, Any]) -> None:
        poses = args.get("poses")
        if not isinstance(poses, list) or not poses:
            self.nav.engine.note("goal rejected: no poses")
            ref.reject()
            return
        parsed = [parse_pose(p) for p in poses]
        bad = next((p for p in parsed if isinstance(p, str)), None)
        if bad is not None:
            self._start(ref, bad, [])
            return
        good = [p for p in parsed if not isinstance(p, str)]
        via = [(p[0][0], p[0][1]) for p in good[:-1]]
        self._start(ref, good[-1], via)


def _duration(seconds: float) -> dict[str, int]:
    """A ``builtin_interfaces/Duration``: a ROS 2 stamp's shape, clamped to what its int32 seconds hold."""
    return make_stamp(max(0.0, min(seconds, 2.0**31 - 1)), 2)
