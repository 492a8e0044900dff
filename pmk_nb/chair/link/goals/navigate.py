"""Send the chair to a pose and follow the goal: one handle over every navigation stack in the field.

Which route a goal takes is detected, like the map reload service:

* ROS 2: Nav2's ``NavigateToPose`` action at ``/navigate_to_pose`` (and ``NavigateThroughPoses`` at
  ``/navigate_through_poses`` for waypoints, when the chair offers it), over rosbridge's action ops;
* ROS 1: ``move_base`` over actionlib when ``/move_base/status`` exists;
* otherwise the goal topic (``/move_base_simple/goal``, Nav2 ``/goal_pose``), with progress derived
  from the chair's pose (arrived within :data:`ARRIVE_TOLERANCE`).

``progress().message`` names the route taken. Waypoints without NavigateThroughPoses are sent one
after another. Updates arrive on roslibpy's I/O thread (or a small poller thread): ``on_update``
callbacks must only store what they get.

The status never claims more than the chair said (issue 24). A goal watch thread
(:mod:`pmk_nb.chair.link.goals.goal_watch`) turns silence into states: ``link_lost`` when the link drops
(rosbridge_suite lets the goal run on), then re-attaches on reconnect; ``no_answer`` (and a cancel)
when nothing accepted the goal in :attr:`GoalPolicy.accept_s`; ``quiet_s`` when the chair said
nothing for :attr:`GoalPolicy.quiet_s`; ``cancel_ignored`` (and zero velocity at 20 Hz for 1 s) when
odometry still shows motion :attr:`GoalPolicy.verify_s` after a cancel.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from pmk_nb.chair.link.goals import goal_routes, goal_stop, heartbeat
from pmk_nb.chair.link.goals.goal import (
    ARRIVE_TOLERANCE,
    LINK_LOSS_POLICIES,
    TERMINAL,
    GoalHandle,
    GoalPolicy,
    GoalProgress,
    GoalRoute,
    GoalStatus,
    NavigationError,
    UpdateCallback,
)
from pmk_nb.chair.link.goals.goal_watch import GoalWatch
from pmk_nb.clock import MONOTONIC, Clock
from pmk_nb.errors import ChairLinkError
from pmk_nb.wire import MOVE_BASE, NAV2_ACTION, NAV2_THROUGH

if TYPE_CHECKING:
    from pmk_nb.chair.link.core import LinkCore

# the goal's types live in .goal (the routes and the watch use them); named here too, as always
__all__ = ["ARRIVE_TOLERANCE", "LINK_LOSS_POLICIES", "MOVE_BASE", "NAV2_ACTION", "NAV2_THROUGH", "TERMINAL"]
__all__ += ["GoalHandle", "GoalPolicy", "GoalProgress", "GoalRoute", "GoalStatus", "NavigationError"]
__all__ += ["UpdateCallback", "detect_route", "navigate"]


def detect_route(link: LinkCore) -> GoalRoute:
    """Ask rosapi which navigation interface the chair offers (see the module docstring)."""
    version = link.ros_version or link.discovery.ros_version()
    if version == 2:
        try:
            reply = link.call("/rosapi/action_servers", "rosapi_msgs/srv/GetActionServers", {}, None)
            servers = set(reply.get("action_servers") or [])
        except ChairLinkError:  # older rosapi: the action's hidden status topic tells the same
            servers = {t.rsplit("/_action/", 1)[0] for t in link.discovery.topics() if "/_action/status" in t}
        if NAV2_ACTION[0] in servers:
            return GoalRoute("nav2", NAV2_ACTION[0], NAV2_THROUGH[0] if NAV2_THROUGH[0] in servers else None)
        return GoalRoute("topic", link.goal_topic or "/goal_pose")
    if f"{MOVE_BASE[0]}/status" in link.discovery.topics():
        return GoalRoute("actionlib", MOVE_BASE[0])
    return GoalRoute("topic", link.goal_topic or "/move_base_simple/goal")


def navigate(
    link: LinkCore,
    x: float,
    y: float,
    yaw: float,
    frame: str = "map",
    waypoints: Sequence[tuple[float, float]] = (),
    *,
    clock: Clock = MONOTONIC,
) -> GoalHandle:
    """Send the chair to (x, y, yaw) in ``frame``, through ``waypoints`` first; see the module docstring.
    ``clock``: the goal's deadlines and its watch's ticks (``GoalHandle.clock``).

    Raises:
        GoalsStopped: a Stop is latched for this chair (``link.goal_gate``).
        NavigationError: not connected, or the goal could not be sent.
        ChairLinkError: rosapi did not answer while detecting the route.
    """
    goal = (float(x), float(y), float(yaw))
    points = [(float(px), float(py)) for px, py in waypoints]
    ros = link.ros
    if ros is None or not ros.is_connected:
        raise NavigationError(
            f"Not connected to the chair at {link.host}:{link.port}: connect first", host=link.host, port=link.port
        )
    goal_stop.check_gate(link)  # a latched Stop refuses every goal (issue 38)
    route = detect_route(link)
    handle = GoalHandle(goal, route.label, clock=clock)
    if route.kind == "nav2":  # odometry verifies a cancel; rosbridge_suite holds a subscribe behind a goal
        link.start_streams()
    if points and route.kind == "nav2" and route.through:
        handle.route = f"Nav2 NavigateThroughPoses ({route.through}), {len(points)} waypoint(s)"
        handle.update(text="sent")
        goal_routes.start_nav2(ros, handle, NAV2_THROUGH, goal_routes.through_poses_args(points, goal, frame, link))
    elif points:
        goal_routes.start_legs(link, route, handle, [*[(px, py, None) for px, py in points], goal], frame)
    else:
        goal_routes.start_leg(link, route, handle, goal, frame)
    # -- goal heartbeat (issue 24, W): beats while this goal runs, "idle" when it ends ----------------
    heartbeat.track(link, handle)
    goal_stop.track(link, handle)  # a Stop cancels it (ChairLink.stop_goals)
    # -- end goal heartbeat ----------------------------------------------------------------------------
    watch = GoalWatch(link, handle, route.kind, getattr(link, "goal_policy", GoalPolicy()))
    # Things that live as long as the goal hook in here: watch.on_end(stop) runs stop() when it ends.
    watch.start()
    return handle
