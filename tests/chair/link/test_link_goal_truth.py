"""Issue 24: after a link loss a goal's status says only what is known, and re-attaches on reconnect.

rosbridge_suite ("official") lets a lost client's goal run on; rs cancels it; ROS 1 move_base goes
over actionlib topics, which run on as well. The setting "when the dashboard loses the chair"
(GoalPolicy.on_link_loss) decides whether the link cancels the goal once it is back.
"""

from __future__ import annotations

import math

import pytest

from pmk_nb.chair.link.goals.navigate import GoalPolicy, GoalProgress, GoalStatus
from tests.fixtures_sim import wait_until

START = (1.0, 6.0, 0.0)
NEAR, FAR = (5.0, 6.0, 0.0), (12.0, 6.0, 0.0)

CASES = [
    # ros, bridge, on_link_loss, goal, what the chair did meanwhile, final status
    ("ros2", "official", "finish", NEAR, "drove on", GoalStatus.ARRIVED),
    ("ros2", "official", "cancel", FAR, "stopped after the reconnect", GoalStatus.CANCELLED),
    ("ros2", "rs", "finish", FAR, "stopped at the drop", GoalStatus.CANCELLED),
    ("ros1", "official", "finish", NEAR, "drove on", GoalStatus.ARRIVED),
]


@pytest.mark.slow
@pytest.mark.parametrize(("ros", "bridge", "on_loss", "goal", "chair", "final_status"), CASES)
def test_link_loss_is_said_truthfully_and_the_goal_reattached(
    sim_factory, link_factory, ros, bridge, on_loss, goal, chair, final_status
) -> None:
    sim = sim_factory(ros=ros, start_pose=START, bridge=bridge)
    link = link_factory(sim)
    link.goal_policy = GoalPolicy(on_link_loss=on_loss)
    handle = link.navigate_to(*goal)
    seen: list[GoalProgress] = []
    handle.on_update(seen.append)
    assert wait_until(lambda: handle.progress().status is GoalStatus.MOVING and sim.velocity[0] > 0.1, 10.0)
    sim.disconnect_clients()
    assert wait_until(lambda: handle.progress().status is GoalStatus.LINK_LOST, 2.0), handle.progress()
    lost = handle.progress()
    assert "may still be driving to (" in lost.message and not lost.done  # never "stopped"
    if chair == "drove on":
        assert wait_until(lambda: False, 0.4) is False and sim.velocity[0] > 0.1
    final = handle.wait(15.0)
    assert final.status is final_status, final
    assert ros == "ros1" or "link back" in final.message  # ROS 1: actionlib's own status says it
    # the last update reaches on_update on the link's thread, maybe just after wait() returned
    assert wait_until(lambda: final_status in [p.status for p in seen], 2.0), seen
    statuses = [p.status for p in seen]
    assert GoalStatus.LINK_LOST in statuses and statuses.index(GoalStatus.LINK_LOST) < statuses.index(final_status)
    if final_status is GoalStatus.ARRIVED:
        assert math.dist(sim.pose[:2], goal[:2]) < 0.3
    else:
        assert sim.pose[0] < goal[0] - 1.0 and wait_until(lambda: sim.velocity == (0.0, 0.0), 1.0)
    if chair == "stopped after the reconnect":  # the cancel went over the new connection
        assert handle.cancel_requested


@pytest.mark.slow
def test_a_goal_the_chair_no_longer_lists_is_read_from_the_pose(sim_factory) -> None:
    """ROS 1: the link is down longer than move_base lists a finished goal (5 s), so no status ever
    names it again: the pose says where the chair is; at the goal -> arrived, said as read from the pose."""
    from pmk_nb.chair.link.client import ChairLink

    sim = sim_factory(ros="ros1", start_pose=START)
    link = ChairLink("127.0.0.1", sim.port, reconnect_initial=9.0, reconnect_max=9.0)
    try:
        link.connect(timeout=10.0)
        handle = link.navigate_to(2.0, 6.0, 0.0)
        assert wait_until(lambda: handle.progress().status is GoalStatus.MOVING, 10.0)
        sim.disconnect_clients()
        assert wait_until(lambda: handle.progress().status is GoalStatus.LINK_LOST, 2.0)
        assert wait_until(lambda: sim.goal_status == "reached", 6.0)  # while the dashboard is away
        final = handle.wait(16.0)
        assert final.status is GoalStatus.ARRIVED, final
        assert "pose is at the goal" in final.message
    finally:
        link.close()


def test_closing_the_link_ends_the_goal_watch(sim_factory, link_factory) -> None:
    """A closed link (not a dropped one) says link lost and its goal watch thread ends: no thread per
    abandoned goal left polling in a long-running kernel."""
    import threading

    sim = sim_factory(ros="ros2", start_pose=START, bridge="rs")
    link = link_factory(sim)
    before = set(threading.enumerate())
    handle = link.navigate_to(*FAR)
    watch = [t for t in threading.enumerate() if t.name == "pmk-goal-watch" and t not in before]
    assert len(watch) == 1
    assert wait_until(lambda: handle.progress().status is GoalStatus.MOVING, 10.0)
    link.close()
    assert wait_until(lambda: not watch[0].is_alive(), 2.0)
    assert handle.progress().status is GoalStatus.LINK_LOST
