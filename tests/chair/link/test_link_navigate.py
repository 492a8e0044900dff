"""Goals through ChairLink.navigate_to with the real roslibpy client against the simulator.

Every route: Nav2 NavigateToPose (ROS 2), move_base actionlib (ROS 1), the goal topic with progress
from the pose (a chair without action servers), and waypoints. Arrive, abort on an unreachable
goal, reject off the map, cancel (the chair stops). Where the bridges differ (issue 24) the Nav2
cases run against both simulator bridge modes: rosbridge_suite ("official") and rs. Link loss and
re-attach are in tests/chair/link/test_link_goal_truth.py.
"""

from __future__ import annotations

import math

import pytest

from pmk_nb.chair.link.goals.navigate import GoalPolicy, GoalProgress, GoalStatus, NavigationError, detect_route
from tests.fixtures_sim import wait_until

START = (1.0, 6.0, 0.0)  # the demo floor's corridor (y 5..7)
GOAL = (6.0, 6.0, 0.0)
TABLE = (2.5, 1.5, 0.0)  # inside the table in the first room: no path
ROUTES = [("ros2", True, "nav2"), ("ros1", True, "actionlib"), ("ros1", False, "topic"), ("ros2", False, "topic")]
# the cancel differs per bridge on the Nav2 route (ROS 1 has no action ops: move_base is topics)
CANCEL_ROUTES = [
    ("ros2", True, "nav2", "rs"),
    ("ros1", True, "actionlib", "official"),
    ("ros1", False, "topic", "official"),
    ("ros2", False, "topic", "official"),
]


def _chair(sim_factory, link_factory, ros: str, actions: bool = True, bridge: str = "official", **policy):
    sim = sim_factory(ros=ros, start_pose=START, nav_actions=actions, bridge=bridge)
    link = link_factory(sim)
    link.goal_policy = GoalPolicy(**policy)
    return sim, link


@pytest.mark.slow
@pytest.mark.parametrize(("ros", "actions", "kind"), ROUTES)
def test_a_goal_arrives_by_the_detected_route(sim_factory, link_factory, ros: str, actions: bool, kind: str) -> None:
    sim, link = _chair(sim_factory, link_factory, ros, actions)
    assert detect_route(link).kind == kind
    handle = link.navigate_to(*GOAL)
    seen: list[GoalProgress] = []
    handle.on_update(seen.append)
    final = handle.wait(30.0)
    assert final.status is GoalStatus.ARRIVED, final
    assert math.dist(sim.pose[:2], GOAL[:2]) < 0.3
    assert final.remaining_m is not None and final.remaining_m < 0.3
    assert final.message.startswith(detect_route(link).label)
    assert GoalStatus.MOVING in {p.status for p in seen}
    # the distance left falls while moving
    left = [p.remaining_m for p in seen if p.status is GoalStatus.MOVING and p.remaining_m is not None]
    assert left and left[0] > left[-1] + 2.0


@pytest.mark.slow
@pytest.mark.parametrize(("ros", "actions", "kind", "bridge"), CANCEL_ROUTES)
def test_cancel_stops_the_chair(sim_factory, link_factory, ros: str, actions: bool, kind: str, bridge: str) -> None:
    sim, link = _chair(sim_factory, link_factory, ros, actions, bridge)
    handle = link.navigate_to(12.0, 6.0, 0.0)
    assert wait_until(lambda: handle.progress().status is GoalStatus.MOVING and sim.velocity[0] > 0.1, 10.0)
    handle.cancel()
    final = handle.wait(3.0)
    assert final.status is GoalStatus.CANCELLED, final
    assert wait_until(lambda: abs(sim.velocity[0]) < 1e-6, 1.0)
    x = sim.pose[0]
    assert wait_until(lambda: False, 0.6) is False and abs(sim.pose[0] - x) < 0.02  # and stays stopped
    assert sim.pose[0] < 11.0
    assert wait_until(lambda: handle.cancel_honoured is True, 1.0) and handle.zero_bursts == 0


@pytest.mark.slow
def test_a_cancel_the_official_bridge_holds_is_not_honoured(sim_factory, link_factory) -> None:
    """rosbridge_suite handles the link's cancel only after the goal: odometry still shows motion
    0.5 s later, so the handle says so, and the cancel and zero velocity at 20 Hz go again over a
    second connection, which that bridge does not hold: the chair stops and says cancelled (fact 3)."""
    sim, link = _chair(sim_factory, link_factory, "ros2", verify_s=0.5)
    twists: list[dict] = []
    sim.bridge.listen("/cmd_vel", "geometry_msgs/msg/Twist", twists.append)  # before the goal: no race
    handle = link.navigate_to(6.0, 6.0, 0.0)
    seen: list[GoalProgress] = []
    handle.on_update(seen.append)
    assert wait_until(lambda: handle.progress().status is GoalStatus.MOVING and sim.velocity[0] > 0.1, 10.0)
    handle.cancel()
    final = handle.wait(5.0)
    assert final.status is GoalStatus.CANCELLED, final  # the chair said so: now that is the truth
    # said once: one run of CANCEL_IGNORED updates (a loaded machine can fit a second feedback into it)
    ignored = [
        p
        for i, p in enumerate(seen)
        if p.status is GoalStatus.CANCEL_IGNORED and (i == 0 or seen[i - 1].status is not GoalStatus.CANCEL_IGNORED)
    ]
    assert len(ignored) == 1 and "did not honour the cancel" in ignored[0].message, seen
    assert handle.cancel_honoured is False and handle.zero_bursts == 1
    assert sim.pose[0] < 5.0 and wait_until(lambda: sim.velocity == (0.0, 0.0), 1.0)
    assert wait_until(lambda: len(twists) >= 18, 2.0), len(twists)  # ~20 zero twists over ~1 s
    assert all(t["linear"]["x"] == 0.0 and t["angular"]["z"] == 0.0 for t in twists)


def test_a_still_chair_right_after_a_cancel_is_not_taken_as_honoured() -> None:
    """CI, stop 34: a cancel sent as soon as the goal was accepted met a chair still at rest; its first
    still odometry was taken as "honoured" while rosbridge_suite held the cancel, and the chair then
    drove to the goal. Now the cancel is judged only after verify_s, and a goal still running
    unanswered then gets the cancel again on a second connection (a burst) before it counts as honoured."""
    from pmk_nb.chair.link.goals.goal_watch import GoalWatch
    from pmk_nb.chair.link.goals.navigate import GoalHandle
    from pmk_nb.chair.link.streams.messages import Odometry
    from pmk_nb.clock import VirtualClock

    clock = VirtualClock()

    class StillChair:  # the link as the watch sees it: odometry of a chair at rest, arriving now
        def start_streams(self) -> None:
            pass

        def latest_odom(self) -> Odometry:
            return Odometry(0.0, 0.0, 0.0, 0.0, 0.0, None, clock.now())

    handle = GoalHandle((6.0, 6.0, 0.0), "Nav2 NavigateToPose", clock=clock)
    handle.update(GoalStatus.MOVING, 5.0)
    watch = GoalWatch(StillChair(), handle, "action", GoalPolicy(verify_s=0.5))  # type: ignore[arg-type]
    bursts: list[float] = []
    watch.zero_burst = lambda: bursts.append(clock.now())  # type: ignore[method-assign]
    handle.cancel()
    since = handle.cancel_at
    assert since is not None
    clock.advance(0.1)
    watch._verify_cancel(since + 0.1)  # before verify_s: not judged, whatever odometry says
    assert handle.cancel_honoured is None and not bursts
    clock.advance(0.5)
    watch._verify_cancel(since + 0.6)  # after: still, but the goal runs on unanswered
    assert bursts and handle.cancel_honoured is True  # honoured only once the cancel went again


@pytest.mark.parametrize("ros", ["ros1", "ros2"])
def test_an_unreachable_goal_is_aborted(sim_factory, link_factory, ros: str) -> None:
    sim, link = _chair(sim_factory, link_factory, ros)
    final = link.navigate_to(*TABLE).wait(15.0)
    assert final.status is GoalStatus.ABORTED, final
    assert "no path" in final.message
    assert sim.velocity == (0.0, 0.0)


@pytest.mark.parametrize(("ros", "bridge"), [("ros1", "official"), ("ros2", "rs")])
def test_a_goal_off_the_map_is_rejected(sim_factory, link_factory, ros: str, bridge: str) -> None:
    _, link = _chair(sim_factory, link_factory, ros, bridge=bridge)
    final = link.navigate_to(250.0, 6.0, 0.0).wait(5.0)
    assert final.status is GoalStatus.REJECTED, final
    assert ("outside the map" if ros == "ros1" else "goal rejected") in final.message  # rs gives no reason


@pytest.mark.slow
def test_no_answer_to_a_goal_is_said_and_cancelled(sim_factory, link_factory) -> None:
    """rosbridge_suite never answers a rejected goal: after accept_s the handle says "no answer"
    (the chair may have started) and sends a cancel; it never claims rejected (fact 2)."""
    sim, link = _chair(sim_factory, link_factory, "ros2", accept_s=0.5)
    handle = link.navigate_to(250.0, 6.0, 0.0)
    assert wait_until(lambda: handle.progress().status is GoalStatus.NO_ANSWER, 2.0), handle.progress()
    assert handle.cancel_requested and not handle.progress().done
    assert "may have started" in handle.progress().message
    # the chair is still, but nothing answers: the cancel goes again on a second connection (with
    # zero velocity for BURST_S), since a held cancel and a chair yet to start look alike; then honoured
    assert wait_until(lambda: handle.cancel_honoured is True, 4.0) and handle.zero_bursts == 1
    assert sim.velocity == (0.0, 0.0)


@pytest.mark.slow
def test_a_silent_goal_is_flagged(sim_factory, link_factory) -> None:
    """No result or feedback for quiet_s: the progress carries how long the chair has been silent."""
    sim, link = _chair(sim_factory, link_factory, "ros2", quiet_s=0.6)
    handle = link.navigate_to(12.0, 6.0, 0.0)
    assert wait_until(lambda: handle.progress().status is GoalStatus.MOVING, 10.0)
    assert handle.progress().quiet_s is None
    sim.pause()  # no feedback, no odometry
    assert wait_until(lambda: (handle.progress().quiet_s or 0.0) > 0.6, 3.0), handle.progress()
    sim.resume()
    assert wait_until(lambda: handle.progress().quiet_s is None, 2.0)  # the chair spoke again


@pytest.mark.slow
@pytest.mark.parametrize(("ros", "actions"), [("ros2", True), ("ros1", True)])
def test_waypoints_are_passed_in_order(sim_factory, link_factory, ros: str, actions: bool) -> None:
    sim, link = _chair(sim_factory, link_factory, ros, actions)
    # into the first room across the corridor and out again, then along the corridor
    handle = link.navigate_to(8.0, 6.0, 0.0, waypoints=[(3.0, 9.0)])
    assert ("NavigateThroughPoses" in handle.progress().message) == (ros == "ros2")
    visited = []
    handle.on_update(lambda p: visited.append(sim.pose[1]))
    final = handle.wait(60.0)
    assert final.status is GoalStatus.ARRIVED, final
    assert max(visited) > 8.0  # went through the room at y = 9
    assert math.dist(sim.pose[:2], (8.0, 6.0)) < 0.3


def test_navigate_needs_a_connection(sim_factory) -> None:
    from pmk_nb.chair.link.client import ChairLink

    sim = sim_factory()
    link = ChairLink("127.0.0.1", sim.port)
    with pytest.raises(NavigationError) as err:
        link.navigate_to(*GOAL)
    assert err.value.port == sim.port


@pytest.mark.slow
def test_cancel_between_waypoints_stops_the_legs(sim_factory, link_factory) -> None:
    sim, link = _chair(sim_factory, link_factory, "ros1")  # actionlib: waypoints go one after another
    handle = link.navigate_to(12.0, 6.0, 0.0, waypoints=[(4.0, 6.0), (8.0, 6.0)])
    assert "one by one" in handle.progress().message
    assert wait_until(lambda: sim.pose[0] > 2.0, 15.0)
    handle.cancel()
    final = handle.wait(3.0)
    assert final.status is GoalStatus.CANCELLED, final
    assert "leg 1/3" in final.message
    x = sim.pose[0]
    assert wait_until(lambda: False, 1.5) is False and abs(sim.pose[0] - x) < 0.02  # no next leg started
