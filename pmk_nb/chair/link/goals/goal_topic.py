"""The goal-topic route: a PoseStamped on ``/move_base_simple/goal`` (or Nav2 ``/goal_pose``) when no
action server is found, with progress read from the chair's own pose.

No server says "accepted" or "arrived" here, so: sent = accepted; moving once the distance falls;
arrived within :data:`pmk_nb.chair.link.goals.navigate.ARRIVE_TOLERANCE`; aborted when the distance has
not fallen by :data:`PROGRESS_STEP` for :data:`NO_PROGRESS_S`. Cancel sends a zero velocity command
(the only stop a plain goal topic offers). A daemon poller thread reads the latest pose at 5 Hz, on the
goal's clock (``GoalHandle.clock``).
"""

from __future__ import annotations

import math
import threading
from typing import TYPE_CHECKING

from pmk_nb.chair.link.goals.goal import ARRIVE_TOLERANCE, GoalHandle, GoalStatus, NavigationError

if TYPE_CHECKING:
    from pmk_nb.chair.link.core import LinkCore

POLL_S = 0.2
NO_PROGRESS_S = 30.0
PROGRESS_STEP = 0.05  # m


def start_topic(link: LinkCore, handle: GoalHandle, goal: tuple[float, float, float], frame: str) -> None:
    if not link.send_goal(goal[0], goal[1], goal[2], frame):
        raise NavigationError(
            "goal not sent: not connected, or the chair's ROS version is not known yet",
            route="goal topic",
            host=link.host,
            port=link.port,
        )
    link.start_streams()  # the pose tells the progress
    handle.update(GoalStatus.ACCEPTED)

    def cancel() -> None:
        link.publish_cmd_vel(0.0, 0.0)
        handle.update(GoalStatus.CANCELLED, text="cancelled: a zero velocity command was sent")

    handle.bind_cancel(cancel)
    threading.Thread(target=_poll, args=(link, handle, goal), daemon=True, name="pmk-goal-topic").start()


def _poll(link: LinkCore, handle: GoalHandle, goal: tuple[float, float, float]) -> None:
    best, best_at = math.inf, handle.clock.now()
    while not handle.wait(POLL_S).done:
        pose = link.latest_pose()
        if pose is None:
            continue
        left = math.dist((pose.x, pose.y), goal[:2])
        now = handle.clock.now()
        if left <= ARRIVE_TOLERANCE:
            handle.update(GoalStatus.ARRIVED, left)
            return
        if left < best - PROGRESS_STEP:
            if best < math.inf:
                handle.update(GoalStatus.MOVING, left)
            best, best_at = left, now
        else:
            handle.update(remaining=left)
        if now - best_at > NO_PROGRESS_S:
            handle.update(GoalStatus.ABORTED, left, f"aborted: no progress for {NO_PROGRESS_S:.0f} s")
            return
