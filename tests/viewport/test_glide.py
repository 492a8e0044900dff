"""The page-drawn chair's maths (issue 41): interpolation, never more than one update ahead, "link slow"."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pmk_nb.viewport import Viewport
from pmk_nb.viewport.glide import (
    LATE_GRACE_S,
    ClockOffset,
    StampedPose,
    late,
    merge,
    pixel_affine,
    pose_at,
    render_time,
)


def poses(*rows: tuple[float, float, float, float]) -> list[StampedPose]:
    return [StampedPose(t, x, y, yaw) for t, x, y, yaw in rows]


def test_between_two_updates_the_chair_moves_linearly() -> None:
    s = poses((1.0, 0.0, 0.0, 0.0), (1.1, 1.0, 2.0, 0.2))
    got = pose_at(s, 1.025)
    assert got is not None
    assert (got.x, got.y, got.yaw) == pytest.approx((0.25, 0.5, 0.05))


def test_yaw_turns_the_short_way_across_pi() -> None:
    s = poses((0.0, 0.0, 0.0, math.pi - 0.1), (1.0, 0.0, 0.0, -math.pi + 0.1))
    got = pose_at(s, 0.5)
    assert got is not None and abs(abs(got.yaw) - math.pi) < 1e-9  # through pi, not through 0


def test_past_the_newest_pose_at_most_one_update_ahead_then_held() -> None:
    s = poses((1.0, 0.0, 0.0, 0.0), (1.05, 0.5, 0.0, 0.1))
    half = pose_at(s, 1.075)
    assert half is not None and half.x == pytest.approx(0.75)
    for t in (1.10, 1.2, 5.0, 1e6):  # one interval ahead, and any later: held there
        got = pose_at(s, t)
        assert got is not None
        assert (got.x, got.yaw) == pytest.approx((1.0, 0.2))
        assert got.t == pytest.approx(1.10)


def test_before_the_first_pose_the_first_and_a_single_pose_is_itself() -> None:
    s = poses((1.0, 3.0, 4.0, 0.5), (2.0, 5.0, 4.0, 0.5))
    assert pose_at(s, 0.0) == s[0]
    assert pose_at(s[:1], 9.0) == s[0]
    assert pose_at([], 1.0) is None


def test_interpolation_finds_the_right_pair_among_many() -> None:
    s = [StampedPose(t * 0.04, t * 0.1, 0.0, 0.0) for t in range(8)]
    got = pose_at(s, 0.04 * 5.5)
    assert got is not None and got.x == pytest.approx(0.55)


def test_merge_keeps_one_per_stamp_in_order_and_restarts_on_an_older_clock() -> None:
    a = poses((1.0, 0, 0, 0), (1.1, 1, 0, 0))
    b = poses((1.1, 2, 0, 0), (1.2, 3, 0, 0), (float("nan"), 0, 0, 0))
    got = merge(a, b)
    assert [p.t for p in got] == [1.0, 1.1, 1.2]
    assert got[1].x == 2  # the newer message wins
    assert [p.t for p in merge(got, poses((0.1, 0, 0, 0)))] == [0.1]  # the kernel restarted
    many = merge([], [StampedPose(float(t), 0, 0, 0) for t in range(20)], keep=5)
    assert [p.t for p in many] == [15, 16, 17, 18, 19]


def test_clock_offset_takes_the_quickest_transit() -> None:
    off = ClockOffset(window=3)
    assert off.add(10.05, 1.0) == pytest.approx(9.05)
    assert off.add(10.12, 1.1) == pytest.approx(9.02)  # this one came faster
    off.add(10.30, 1.2)
    off.add(10.40, 1.3)
    off.add(10.50, 1.4)  # the quick one left the window
    assert off.offset == pytest.approx(9.1)
    assert render_time(20.0, 9.0, 0.04) == pytest.approx(10.96)
    assert render_time(20.0, 9.0, -1.0) == pytest.approx(11.0)  # never ahead of the kernel's now


def test_late_after_the_promise_and_the_grace() -> None:
    assert not late(10.0 + 0.04 + LATE_GRACE_S - 0.01, 10.0, 0.04)
    assert late(10.0 + 0.04 + LATE_GRACE_S + 0.01, 10.0, 0.04)
    assert not late(10.6, 10.0, 0.5)  # a parked chair's heartbeat
    assert not late(1e9, 10.0, None)  # nothing promised: the view is not running


def test_pixel_affine_is_the_views_world_to_pixel() -> None:
    view = Viewport(300, 200, 0.05, (-1.0, -2.0), 320, 240)
    view.set_zoom(3)
    view.see_chair(4.0, 3.0)
    ax, bx, ay, by = pixel_affine(view)
    xs, ys = np.array([-1.0, 2.5, 11.0]), np.array([-2.0, 0.3, 7.0])
    px, py = view.world_to_pixel(xs, ys)
    assert np.allclose(ax * xs + bx, px) and np.allclose(ay * ys + by, py)
    assert ay < 0 < ax  # north up
