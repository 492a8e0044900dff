"""The simulated chair on a virtual clock (issue 39): its physics and loops step only as the test
advances time, so a pose after a span is exact, whatever the machine's load.

A 64 Hz odometry loop (a period exact in binary) and 0.5 m/s straight ahead: each step moves the chair
by exactly 0.0078125 m; the command holds for ``cmd_timeout`` (0.5 s) and not one step longer.
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from pmk_nb.clock import VirtualClock
from pmk_nb.sim.server import SimChair
from tests.fixtures_sim import room_grid

ODOM_HZ = 64.0
STEP_M = 0.5 / ODOM_HZ  # 0.0078125 m a step at 0.5 m/s


@pytest.fixture
def clock() -> VirtualClock:
    return VirtualClock(start=1000.0)


@pytest.fixture
def chair(clock: VirtualClock) -> Iterator[SimChair]:
    sim = SimChair(
        grid=room_grid(), start_pose=(1.0, 1.0, 0.0), odom_rate=ODOM_HZ, scan_rate=8.0, clock=clock, wall_clock=clock
    )
    sim.start()
    try:
        # the odometry, scan and navigation loops each wait on the clock before time moves
        assert clock.wait_for_waiters(3), "the simulator's loops never waited on the virtual clock"
        yield sim
    finally:
        sim.stop()


def test_a_command_moves_the_chair_exactly_as_far_as_the_advanced_time_allows(
    chair: SimChair, clock: VirtualClock
) -> None:
    chair.drive(0.5, 0.0)
    assert chair.pose == (1.0, 1.0, 0.0), "no time passed: no step"
    clock.advance(0.25)
    assert chair.pose == (1.0 + 16 * STEP_M, 1.0, 0.0) == (1.125, 1.0, 0.0)
    assert chair.velocity == (0.5, 0.0)
    clock.advance(1.0)
    # the command holds for cmd_timeout (0.5 s: 32 steps, the last one at exactly 0.5 s), then the chair stops
    assert chair.pose == (1.0 + 32 * STEP_M, 1.0, 0.0) == (1.25, 1.0, 0.0)
    assert chair.velocity == (0.0, 0.0)


def test_a_parked_chair_stays_put_however_long_time_runs(chair: SimChair, clock: VirtualClock) -> None:
    clock.advance(30.0)
    assert chair.pose == (1.0, 1.0, 0.0) and chair.velocity == (0.0, 0.0)
    chair.drive(0.0, 1.0)  # a turn on the spot: 1 rad/s for 0.5 s
    clock.advance(0.5)
    assert chair.pose[:2] == (1.0, 1.0) and chair.pose[2] == pytest.approx(0.5, abs=1e-12)
