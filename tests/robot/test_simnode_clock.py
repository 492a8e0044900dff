"""The ROS 2 simulator node's physics on virtual time (issue 39): a step moves the chair by exactly the
time its clock advanced, and a command holds for ``cmd_timeout`` of that clock, not of the wall's."""

from __future__ import annotations

import math

import pytest

from pmk_nb.clock import VirtualClock
from pmk_nb.robot.simnode import SimState
from tests.fixtures_sim import room_grid


def test_a_step_moves_the_chair_by_the_time_the_clock_advanced() -> None:
    clock = VirtualClock(start=1000.0)
    state = SimState(room_grid(), (0.0, 0.0, 0.0), rays=8, clock=clock)
    x0, y0, th0 = state.chair.pose
    state.command(0.5, 0.0)
    clock.advance(0.25)
    pose, v, _w = state.step()
    assert v == 0.5 and pose == pytest.approx((x0 + 0.125 * math.cos(th0), y0 + 0.125 * math.sin(th0), th0), abs=1e-12)
    clock.advance(0.3)  # 0.55 s after the command: past cmd_timeout (0.5 s), the chair stands
    again, v, _w = state.step()
    assert v == 0.0 and again == pose
