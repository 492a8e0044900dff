"""The simulated chair on a virtual clock (issue 39): its physics and loops step only as the test
advances time, so a pose after a span is exact, whatever the machine's load.

A 64 Hz odometry loop (a period exact in binary) and 0.5 m/s straight ahead: each step moves the chair
by exactly 0.0078125 m; the command holds for ``cmd_timeout`` (0.5 s) and not one step longer.
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from pmk_nb.clock import VirtualClock
from pmk_nb.sim.config import SimConfig
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
        SimConfig(
            grid=room_grid(),
            start_pose=(1.0, 1.0, 0.0),
            odom_rate=ODOM_HZ,
            scan_rate=8.0,
            clock=clock,
            wall_clock=clock,
        )
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
    clock.advance(5.0)
    assert chair.pose == (1.0, 1.0, 0.0) and chair.velocity == (0.0, 0.0)
    chair.drive(0.0, 1.0)  # a turn on the spot: 1 rad/s for 0.5 s
    clock.advance(0.5)
    assert chair.pose[:2] == (1.0, 1.0) and chair.pose[2] == pytest.approx(0.5, abs=1e-12)


def _push_into_the_wall(clock: VirtualClock) -> tuple[tuple[float, float, float], bool, tuple[float, float]]:
    """0.8 m/s at a wall 1.5 m ahead for 3 s of virtual time, the command renewed every 0.25 s."""
    sim = SimChair(
        SimConfig(grid=room_grid(6.0, 4.0, wall_x=3.0), start_pose=(1.5, 2.0, 0.0), odom_rate=ODOM_HZ, clock=clock)
    ).start()
    try:
        assert clock.wait_for_waiters(3)
        for _ in range(12):
            sim.drive(0.8, 0.0)
            clock.advance(0.25)
        return sim.pose, sim.bumped, sim.velocity
    finally:
        sim.stop()


def test_the_same_drive_into_a_wall_ends_at_the_same_pose_bit_for_bit() -> None:
    pose, bumped, velocity = _push_into_the_wall(VirtualClock(start=1000.0))
    assert bumped and velocity == (0.0, 0.0) and pose[1:] == (2.0, 0.0)
    # the footprint (0.35 m) meets the wall cells (x from 3.0) to within a cell
    assert 3.0 - 0.35 - 0.15 < pose[0] < 3.0 - 0.35 + 0.05, pose
    steps = (pose[0] - 1.5) / (0.8 / ODOM_HZ)
    assert steps == pytest.approx(round(steps), abs=1e-9), "it stopped on a whole step: no move was cut short"
    assert _push_into_the_wall(VirtualClock(start=1000.0)) == (pose, bumped, velocity), "deterministic"
