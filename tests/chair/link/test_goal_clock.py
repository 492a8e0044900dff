"""A goal's deadlines, its cancel verification and the Stop's bursts on virtual time (issue 39).

The goal watch, the goal-topic poller and the Stop run on threads that wait on the goal's clock
(``GoalHandle.clock``, ``stop_goals(clock=...)``); a ``VirtualClock`` runs exactly the ticks of each
advanced span, so each deadline is asserted to the tick: nothing just before it, the outcome just
after, and nothing more later. The link is a fake whose odometry and pose are stamped on the same clock.
(The same against a simulated chair and real roslibpy: test_link_navigate.py, test_goal_stop.py.)
"""

from __future__ import annotations

import json
import threading
from collections.abc import Iterator
from typing import Any

import pytest

from pmk_nb.chair.link.goals import goal_stop, goal_watch
from pmk_nb.chair.link.goals.goal import GoalHandle, GoalPolicy, GoalStatus
from pmk_nb.chair.link.goals.goal_topic import NO_PROGRESS_S, start_topic
from pmk_nb.chair.link.goals.goal_watch import BURST_HZ, BURST_S, REATTACH_S, GoalWatch
from pmk_nb.chair.link.streams.messages import Odometry, Pose2D
from pmk_nb.clock import VirtualClock
from pmk_nb.goalbeat import STOP_REPEAT_HZ, STOP_REPEAT_S, STOP_TOPIC

GOAL = (5.0, 0.0, 0.0)
BURST = round(BURST_HZ * BURST_S)  # zero twists in one burst of the goal watch


class FakeRos:
    is_connected = True


class FakeLink:
    """The link as the goal watch sees it; odometry and pose arrive "now" on the test's clock."""

    host, port, ros_version, cmd_vel_topic, goal_topic = "127.0.0.1", 9090, 2, "/cmd_vel", None

    def __init__(self, clock: VirtualClock) -> None:
        self.clock = clock
        self.ros: Any = FakeRos()
        self.is_connected = True
        self.moving_until = -1.0  # odometry shows motion until this time
        self.odom_on = True
        self.position = (0.0, 0.0)
        self.zeros: list[float] = []  # when each zero twist went out on the link
        self.goals: list[tuple[float, float, float]] = []

    def start_streams(self) -> None:
        pass

    def latest_odom(self) -> Odometry | None:
        if not self.odom_on:
            return None
        now = self.clock.now()
        v = 0.5 if now < self.moving_until else 0.0
        return Odometry(self.position[0], self.position[1], 0.0, v, 0.0, None, now)

    def latest_pose(self) -> Pose2D:
        return Pose2D(self.position[0], self.position[1], 0.0, "map", self.clock.now())

    def publish_cmd_vel(self, v: float, w: float, topic: str | None = None) -> bool:
        assert (v, w) == (0.0, 0.0)
        self.zeros.append(self.clock.now())
        return True

    def send_goal(self, x: float, y: float, theta: float, frame: str = "map") -> bool:
        self.goals.append((x, y, theta))
        return True


@pytest.fixture
def clock() -> VirtualClock:
    return VirtualClock(start=0.0)


@pytest.fixture
def link(clock: VirtualClock, monkeypatch: pytest.MonkeyPatch) -> Iterator[FakeLink]:
    fake = FakeLink(clock)
    # no second connection: the watch's burst goes over the link, where the fake counts it
    monkeypatch.setattr(goal_watch, "side_stop", lambda *args, **kwargs: False)
    yield fake
    fake.ros = None  # the link closed: every watch ends at its next tick
    clock.advance(1.0)


def _watch(link: FakeLink, handle: GoalHandle, clock: VirtualClock, **policy: Any) -> GoalWatch:
    watch = GoalWatch(link, handle, "nav2", GoalPolicy(**policy))  # type: ignore[arg-type]
    watch.start()
    assert clock.wait_for_waiters(1), "the goal watch never waited on the clock"
    return watch


def test_no_acceptance_within_accept_s_is_said_and_cancelled_at_the_deadline(
    clock: VirtualClock, link: FakeLink
) -> None:
    handle = GoalHandle(GOAL, "Nav2", clock=clock)
    _watch(link, handle, clock, accept_s=5.0, verify_s=1.0, quiet_s=30.0)
    clock.advance(4.9)
    assert handle.progress().status is GoalStatus.PENDING and not handle.cancel_requested
    clock.advance(0.2)
    assert handle.progress().status is GoalStatus.NO_ANSWER and handle.cancel_requested
    assert handle.cancel_at is not None and 5.0 < handle.cancel_at <= 5.1
    assert link.zeros == []
    # the chair is still but nothing answers (a held cancel looks the same): after verify_s the cancel
    # again with one burst of zero velocity, BURST_S long, then nothing more
    clock.advance(0.8)
    assert link.zeros == [] and handle.zero_bursts == 0
    clock.advance(0.3 + BURST_S)
    assert handle.zero_bursts == 1 and len(link.zeros) == BURST
    assert link.zeros[-1] - link.zeros[0] == pytest.approx(BURST_S - 1 / BURST_HZ, abs=1e-6)
    clock.advance(40.0)
    assert handle.zero_bursts == 1 and len(link.zeros) == BURST, "one burst, nothing after"
    assert handle.progress().quiet_s is not None and handle.progress().quiet_s >= 30.0  # silence is said


def test_odometry_still_moving_after_verify_s_is_cancel_ignored_with_one_burst(
    clock: VirtualClock, link: FakeLink
) -> None:
    handle = GoalHandle(GOAL, "Nav2", clock=clock)
    handle.update(GoalStatus.MOVING, 5.0)
    link.moving_until = 1000.0  # the chair drives on whatever it is told
    _watch(link, handle, clock, verify_s=1.0)
    clock.advance(1.0)
    handle.cancel()  # at t = 1.0
    clock.advance(0.9)
    assert handle.cancel_honoured is None and handle.progress().status is GoalStatus.MOVING
    clock.advance(0.2)  # verify_s has passed: judged at the first tick after t = 2.0
    assert handle.cancel_honoured is False and handle.progress().status is GoalStatus.CANCEL_IGNORED
    assert 2.0 < link.zeros[0] <= 2.1
    clock.advance(BURST_S)
    assert len(link.zeros) == BURST and handle.zero_bursts == 1
    clock.advance(10.0)
    assert len(link.zeros) == BURST, "judged once: one burst and nothing after"


def test_a_cancel_the_chair_honours_sends_no_zero_and_the_watch_ends(clock: VirtualClock, link: FakeLink) -> None:
    handle = GoalHandle(GOAL, "Nav2", clock=clock)
    handle.bind_cancel(lambda: handle.update(GoalStatus.CANCELLED))  # the chair confirms at once
    handle.update(GoalStatus.MOVING, 5.0)
    link.moving_until = 0.3  # and its odometry shows it stopping 0.3 s later
    watch = _watch(link, handle, clock, verify_s=1.0)
    handle.cancel()
    clock.advance(0.95)
    assert handle.cancel_honoured is None, "not judged before verify_s"
    clock.advance(0.1)
    assert handle.cancel_honoured is True and handle.progress().status is GoalStatus.CANCELLED
    clock.advance(0.1)
    watch._thread.join(10.0)
    assert not watch._thread.is_alive(), "a verified, finished goal is no longer watched"
    assert link.zeros == [] and handle.zero_bursts == 0


def test_after_a_link_loss_the_pose_decides_only_after_reattach_s(clock: VirtualClock, link: FakeLink) -> None:
    handle = GoalHandle(GOAL, "Nav2", clock=clock)
    handle.update(GoalStatus.MOVING, 5.0)
    _watch(link, handle, clock)
    link.is_connected = False
    clock.advance(0.06)
    assert handle.progress().status is GoalStatus.LINK_LOST
    link.position = GOAL[:2]  # meanwhile the chair drove on to the goal
    clock.advance(10.0)
    assert handle.progress().status is GoalStatus.LINK_LOST, "no word while the link is down"
    link.is_connected = True  # back at t ~ 10.06
    clock.advance(REATTACH_S - 0.1)
    assert handle.progress().status is GoalStatus.LINK_LOST, "the chair's own word is awaited first"
    clock.advance(0.2)
    assert handle.progress().status is GoalStatus.ARRIVED, handle.progress()


class FakeFollower:
    """Nav2's ``_action/status`` as the goal watch reads it after a reconnect."""

    def __init__(self) -> None:
        self.uuid: tuple[int, ...] | None = (1, 2, 3)
        self.code: int | None = None
        self.listed = False
        self.heard_at = 0.0

    def close(self) -> None:
        pass


def test_after_a_link_loss_the_chairs_status_heard_after_the_reconnect_decides_at_once(
    clock: VirtualClock, link: FakeLink
) -> None:
    handle = GoalHandle(GOAL, "Nav2", clock=clock)
    handle.update(GoalStatus.MOVING, 5.0)
    follower = handle.follower = FakeFollower()
    _watch(link, handle, clock)
    link.is_connected = False
    clock.advance(1.0)
    follower.code, follower.listed, follower.heard_at = 4, True, clock.now()  # heard while the link was down
    link.is_connected = True
    clock.advance(0.06)
    assert handle.progress().status is GoalStatus.LINK_LOST, "a status from before the reconnect proves nothing"
    follower.heard_at = clock.now()  # the chair's status after the reconnect: succeeded
    clock.advance(0.06)
    assert handle.progress().status is GoalStatus.ARRIVED and "link back" in handle.progress().message


def test_a_goal_topic_goal_without_progress_is_aborted_after_no_progress_s(clock: VirtualClock, link: FakeLink) -> None:
    handle = GoalHandle((3.0, 0.0, 0.0), "goal topic", clock=clock)
    start_topic(link, handle, (3.0, 0.0, 0.0), "map")  # type: ignore[arg-type]
    assert link.goals == [(3.0, 0.0, 0.0)] and clock.wait_for_waiters(1)
    clock.advance(NO_PROGRESS_S)  # the distance was first read at the first poll (t = 0.2)
    assert handle.progress().status is GoalStatus.ACCEPTED
    clock.advance(0.5)
    final = handle.progress()
    assert final.status is GoalStatus.ABORTED and final.remaining_m == 3.0


def test_a_goal_topic_goal_arrives_when_the_pose_is_within_tolerance(clock: VirtualClock, link: FakeLink) -> None:
    handle = GoalHandle((3.0, 0.0, 0.0), "goal topic", clock=clock)
    start_topic(link, handle, (3.0, 0.0, 0.0), "map")  # type: ignore[arg-type]
    assert clock.wait_for_waiters(1)
    clock.advance(1.0)
    link.position = (1.0, 0.0)
    clock.advance(0.2)
    assert handle.progress().status is GoalStatus.MOVING and handle.progress().remaining_m == 2.0
    link.position = (2.9, 0.0)
    clock.advance(0.2)
    assert handle.progress().status is GoalStatus.ARRIVED


class FakeSocket:
    def __init__(self, sent: list[tuple[float, dict[str, Any]]], clock: VirtualClock) -> None:
        self.sent, self.clock = sent, clock

    def send(self, text: str) -> None:
        self.sent.append((self.clock.now(), json.loads(text)))

    def __enter__(self) -> FakeSocket:
        return self

    def __exit__(self, *exc: object) -> None:
        pass


def test_the_stop_sends_its_zero_burst_then_repeats_itself_for_stop_repeat_s_then_nothing(
    clock: VirtualClock, link: FakeLink, monkeypatch: pytest.MonkeyPatch
) -> None:
    sent: list[tuple[float, dict[str, Any]]] = []
    monkeypatch.setattr(goal_stop, "side_connect", lambda *args, **kwargs: FakeSocket(sent, clock))

    def published(topic: str) -> list[float]:
        return [t for t, m in sent if m["op"] == "publish" and m["topic"] == topic]

    before_threads = set(threading.enumerate())
    goal_stop.stop_goals(link, wait=False, clock=clock)  # type: ignore[arg-type]
    assert clock.wait_for_waiters(1)
    assert published("/cmd_vel") == [0.0], "the cancels and the first zero at once"
    clock.advance(goal_stop.BURST_S)
    burst = round(goal_stop.BURST_HZ * goal_stop.BURST_S)
    assert len(published("/cmd_vel")) == burst
    # the repeat runs on a thread of its own, started as the burst ended: it waits on the clock before time moves on
    assert clock.wait_for_waiters(1)
    before = 1 + burst  # the Stop in the ops, and one beside each zero
    repeats = round(STOP_REPEAT_S * STOP_REPEAT_HZ)
    clock.advance(STOP_REPEAT_S - 0.05)
    assert len(published(STOP_TOPIC)) == before + repeats, "one every 1/STOP_REPEAT_HZ s, the first at once"
    clock.advance(60.0)
    assert len(published("/cmd_vel")) == burst and len(published(STOP_TOPIC)) == before + repeats, "then nothing"
    assert not set(threading.enumerate()) - before_threads, "the Stop's threads ended"
