"""Nav2's ``<action>/_action/cancel_goal`` services (``action_msgs/srv/CancelGoal``), as rclcpp's action
server answers them: a zero goal id and a zero stamp cancel every goal of the action, a goal id cancels
that goal, a stamp every goal accepted at or before it. This is how a client that did not send a goal
(another page's dashboard, ``pmk robot goal-watchdog``) stops it: the rosbridge ``cancel_action_goal``
op only reaches goals the bridge itself sent (and rosbridge-server-rs only the same connection's).

Return codes: 0 accepted (``goals_canceling`` lists them), 1 rejected, 2 unknown goal id, 3 the goal had
already ended.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from pmk_nb.sim.session import resolve_name
from pmk_nb.wire import CANCEL_ERROR_NONE as ERROR_NONE
from pmk_nb.wire import CANCEL_ERROR_UNKNOWN_GOAL_ID as ERROR_UNKNOWN_GOAL_ID
from pmk_nb.wire import NAV2_ACTION

if TYPE_CHECKING:
    from pmk_nb.sim.navroles import GoalKeeper

TOPIC_ACTION = NAV2_ACTION[0]  # what Nav2's /goal_pose becomes (bt_navigator's own goal)


def add_cancel_services(nav: GoalKeeper, actions: tuple[str, ...]) -> None:
    """Serve ``<action>/_action/cancel_goal`` for each of ``actions`` on the navigator's bridge."""
    bridge = nav.bridge
    assert bridge is not None
    for action in actions:

        async def handler(args: dict[str, Any], action: str = action) -> tuple[dict[str, Any], bool]:
            return cancel_goal(nav, action, args), True

        bridge.add_service(f"{action}/_action/cancel_goal", nav.engine.names.srv("action_msgs", "CancelGoal"), handler)


def cancel_goal(nav: GoalKeeper, action: str, args: dict[str, Any]) -> dict[str, Any]:
    """The CancelGoal answer; cancels the running goal of ``action`` when the request names it (or all).

    A goal sent on Nav2's ``/goal_pose`` topic is a NavigateToPose goal of bt_navigator's own: a
    cancel-all of ``/navigate_to_pose`` ends it too. A stamp alone names every goal accepted before
    it: the running goal was, so it counts as all."""
    info = args.get("goal_info")
    goal_id = info.get("goal_id") if isinstance(info, dict) else None
    raw = goal_id.get("uuid") if isinstance(goal_id, dict) else None
    uuid = tuple(int(b) for b in raw if isinstance(b, int)) if isinstance(raw, list) else ()
    goal = nav.current
    if goal is None:
        return {"return_code": ERROR_NONE if not any(uuid) else ERROR_UNKNOWN_GOAL_ID, "goals_canceling": []}
    if goal.ref is not None:
        ours, goal_uuid = resolve_name(goal.ref.action) == action, goal.ref.uuid
    else:
        ours, goal_uuid = goal.kind == "topic" and action == TOPIC_ACTION, ()
    if not ours or (any(uuid) and uuid != goal_uuid):
        return {"return_code": ERROR_UNKNOWN_GOAL_ID if any(uuid) else ERROR_NONE, "goals_canceling": []}
    entry = {"goal_id": {"uuid": list(goal_uuid) or [0] * 16}, "stamp": {"sec": 0, "nanosec": 0}}
    nav.cancel_current("cancelled through the action's cancel_goal service")
    return {"return_code": ERROR_NONE, "goals_canceling": [entry]}
