"""The odometry trail by header stamp (issue 40): interpolated, yaw the short way, clock jumps restart it."""

from __future__ import annotations

import math

import pytest

from pmk_nb.viewport.posetrail import LATE_SLACK_S, PoseTrail, pose_at_stamp


def test_the_trail_interpolates_between_the_samples_around_a_stamp() -> None:
    trail = PoseTrail()
    trail.add(1.0, (0.0, 0.0, 0.0))
    trail.add(2.0, (1.0, 2.0, 1.0))
    assert trail.at(1.25) == pytest.approx((0.25, 0.5, 0.25))
    assert trail.at(2.0) == pytest.approx((1.0, 2.0, 1.0))
    assert trail.at(2.0 + LATE_SLACK_S / 2) == pytest.approx((1.0, 2.0, 1.0))
    assert trail.at(2.0 + 2 * LATE_SLACK_S) is None  # newer than anything seen: the trail cannot tell
    assert trail.at(0.5) is None  # older than the trail
    assert trail.at(None) is None and trail.at(math.nan) is None


def test_yaw_is_interpolated_the_short_way_across_pi() -> None:
    trail = PoseTrail()
    trail.add(0.0, (0.0, 0.0, math.pi - 0.1))
    trail.add(1.0, (0.0, 0.0, -math.pi + 0.1))
    got = trail.at(0.5)
    assert got is not None and abs(math.remainder(got[2] - math.pi, math.tau)) < 1e-9


def test_a_clock_that_jumps_back_starts_the_trail_again_and_repeats_add_nothing() -> None:
    trail = PoseTrail(size=4)
    trail.add(5.0, (1.0, 0.0, 0.0))
    trail.add(5.0, (9.0, 9.0, 0.0))  # the same stamp again: ignored
    assert trail.at(5.0) == pytest.approx((1.0, 0.0, 0.0))
    trail.add(1.0, (2.0, 0.0, 0.0))
    assert len(trail) == 1 and trail.at(5.0) is None
    trail.add(None, (0.0, 0.0, 0.0))
    trail.add(2.0, (math.nan, 0.0, 0.0))
    assert len(trail) == 1
    for i in range(10):
        trail.add(2.0 + i, (float(i), 0.0, 0.0))
    assert len(trail) == 4  # bounded


def test_the_pose_at_a_stamp_carries_the_odometry_motion_into_the_drawn_frame() -> None:
    trail = PoseTrail()
    trail.add(0.0, (0.0, 0.0, 0.0))
    trail.add(1.0, (1.0, 0.0, math.pi / 2))
    # the map frame is the odom frame turned by 90 degrees and shifted: the chair now at (5, 5, pi)
    then = pose_at_stamp((5.0, 5.0, math.pi), trail, 0.0)
    assert then is not None
    # at stamp 0 the chair was 1 m behind its current position along the old heading (odom +x = map +y)
    assert then[:2] == pytest.approx((5.0, 4.0))
    assert abs(math.remainder(then[2] - math.pi / 2, math.tau)) < 1e-9
    assert pose_at_stamp((5.0, 5.0, 0.0), trail, -3.0) is None
