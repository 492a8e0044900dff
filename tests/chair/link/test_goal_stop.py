"""Issue 38: ``ChairLink.stop_goals`` stops a navigation goal, this link's and another dashboard's.

The attacker's case: page A's link sends a goal, page B's link (another kernel: another ChairLink, its
own websocket) presses Stop. Zero velocity alone no longer stops the simulator (tests/sim/
test_sim_foreign_cmd_vel.py), so these pass only when B's Stop cancels natively: Nav2's cancel_goal
service with a zero id, move_base's empty GoalID; in each bridge mode. A latched Stop closes the goal
gate: ``navigate_to`` raises GoalsStopped and sends nothing.
"""

from __future__ import annotations

import json
import math

import pytest

from pmk_nb.chair.link import GoalsStopped, GoalStatus
from pmk_nb.chair.link.goals.goal_stop import running
from pmk_nb.goalbeat import STOP_TOPIC
from tests.fixtures_sim import wait_until

START = (1.0, 6.0, 0.0)
FAR = (14.0, 6.0, 0.0)
MODES = [("ros2", "official"), ("ros2", "rs"), ("ros1", "official")]


def _moving(sim, link_a):
    handle = link_a.navigate_to(*FAR)
    assert wait_until(lambda: handle.progress().status is GoalStatus.MOVING and sim.velocity[0] > 0.2, 10.0)
    return handle


def _stays_stopped(sim) -> None:
    assert wait_until(lambda: sim.velocity == (0.0, 0.0), 2.0), sim.velocity
    x = sim.pose[0]
    assert wait_until(lambda: False, 1.0) is False and math.isclose(sim.pose[0], x, abs_tol=0.02)
    assert sim.goal_status == "cancelled"


@pytest.mark.slow
@pytest.mark.parametrize(("ros", "bridge"), MODES)
def test_another_pages_stop_cancels_the_goal(sim_factory, link_factory, ros: str, bridge: str) -> None:
    sim = sim_factory(ros=ros, start_pose=START, bridge=bridge)
    stops: list[dict] = []
    kind = "std_msgs/msg/String" if ros == "ros2" else "std_msgs/String"
    sim.bridge.listen(STOP_TOPIC, kind, stops.append)
    link_a, link_b = link_factory(sim), link_factory(sim)
    handle = _moving(sim, link_a)
    assert link_b.stop_goals(wait=True) == []  # B runs no goal of its own; the chair's goal is A's
    _stays_stopped(sim)
    assert wait_until(lambda: handle.progress().status is GoalStatus.CANCELLED, 3.0), handle.progress()
    assert stops and json.loads(stops[-1]["data"])["stop"] is True  # the watchdog's stop topic


@pytest.mark.slow
@pytest.mark.parametrize(("ros", "bridge"), MODES)
def test_this_pages_stop_cancels_its_own_goal(sim_factory, link_factory, ros: str, bridge: str) -> None:
    sim = sim_factory(ros=ros, start_pose=START, bridge=bridge)
    link = link_factory(sim)
    handle = _moving(sim, link)
    assert running(link) == [handle]
    assert link.stop_goals() == [handle] and handle.cancel_requested
    _stays_stopped(sim)
    assert wait_until(lambda: handle.progress().status is GoalStatus.CANCELLED, 3.0), handle.progress()
    assert running(link) == []


def test_a_latched_stop_refuses_a_goal(sim_factory, link_factory) -> None:
    sim = sim_factory(ros="ros2", start_pose=START)
    link = link_factory(sim)
    link.goal_gate = lambda: 1234.5
    with pytest.raises(GoalsStopped) as caught:
        link.navigate_to(*FAR)
    assert caught.value.stop_at == 1234.5 and caught.value.port == sim.port
    assert running(link) == [] and wait_until(lambda: False, 0.3) is False and sim.goal_status == "idle"
    link.goal_gate = lambda: None  # released: goals go again
    handle = link.navigate_to(*FAR)
    assert wait_until(lambda: handle.progress().status is GoalStatus.MOVING, 10.0)


def test_a_stop_latched_while_a_goal_is_being_sent_cancels_it(sim_factory, link_factory) -> None:
    """The gate let the goal through, then another page's Stop latched before the goal was tracked
    (its watch found nothing to cancel): the goal is cancelled as soon as it is tracked."""
    sim = sim_factory(ros="ros2", start_pose=START, bridge="rs")
    link = link_factory(sim)
    answers = iter([None])
    link.goal_gate = lambda: next(answers, 99.0)  # open at the gate, latched from then on
    handle = link.navigate_to(*FAR)
    assert handle.cancel_requested
    assert wait_until(lambda: handle.progress().status is GoalStatus.CANCELLED, 5.0), handle.progress()
    assert sim.velocity == (0.0, 0.0) and running(link) == []
