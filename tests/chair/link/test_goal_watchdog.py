"""The goal heartbeat and the watchdog's decisions (issue 24): a lost tablet must end its goals.

Unit tests of :class:`~pmk_nb.robot.goalwatch.GoalWatch` with an injected clock, the wire format,
and the link's heartbeat against the simulator (real roslibpy): "active" at 2 Hz while a goal
runs, "idle" when it ends, silence when the link drops. The real-stack tiers (rclpy + rosbridge,
rospy + rosmaster) are in tests/real/test_real_watchdog.py.
"""

from __future__ import annotations

import threading
import time
from typing import Any

import pytest

from pmk_nb.chair.link.goals import heartbeat
from pmk_nb.chair.link.goals.navigate import GoalStatus
from pmk_nb.clock import VirtualClock
from pmk_nb.goalbeat import RATE_HZ, TOPIC, Beat
from pmk_nb.robot.goalwatch import Change, GoalWatch, Trip
from tests.fixtures_sim import wait_until
from tests.page_probes import FreezableProxy

START = (1.0, 6.0, 0.0)  # the demo floor's corridor
FAR = (12.0, 6.0, 0.0)  # a goal that takes a while


def active(client: str = "tab", goals: int = 1) -> Beat:
    return Beat(client, True, goals)


def test_silence_while_armed_trips_once_after_the_timeout() -> None:
    clock = VirtualClock(start=100.0)
    watch = GoalWatch(3.0, clock)
    assert watch.tick() == []  # nothing armed: silence means nothing
    assert watch.beat(active()) == Change("tab", True)
    assert watch.beat(active()) is None  # already armed
    clock.advance(2.9)
    assert watch.tick() == []
    watch.beat(active(goals=2))  # a beat restarts the count
    clock.advance(2.99)
    assert watch.tick() == []
    clock.advance(0.02)
    assert watch.tick() == [Trip("tab", pytest.approx(3.01), 2)]
    clock.advance(10)
    assert watch.tick() == []  # one trip per silence: disarmed after it
    assert watch.armed == ()


def test_idle_disarms_so_a_finished_goal_is_not_cancelled() -> None:
    clock = VirtualClock(start=100.0)
    watch = GoalWatch(3.0, clock)
    watch.beat(active())
    assert watch.beat(Beat("tab", False)) == Change("tab", False)
    assert watch.beat(Beat("tab", False)) is None  # the second idle beat changes nothing
    clock.advance(60)
    assert watch.tick() == []


def test_each_dashboard_is_armed_on_its_own() -> None:
    clock = VirtualClock(start=100.0)
    watch = GoalWatch(3.0, clock)
    watch.beat(active("a"))
    watch.beat(active("b"))
    watch.beat(Beat("a", False))  # a finished: b still drives
    clock.advance(2.0)
    watch.beat(active("b"))
    clock.advance(2.0)
    assert watch.tick() == []
    clock.advance(1.5)
    assert [t.client for t in watch.tick()] == ["b"]


def test_the_timeout_must_be_positive() -> None:
    with pytest.raises(ValueError):
        GoalWatch(0.0)


@pytest.mark.parametrize(
    "text",
    [
        "",
        "not json",
        "[]",
        '{"active": true}',
        '{"client": "", "active": true}',
        '{"client": "a", "active": "yes"}',
        '{"client": "a", "active": true, "goals": "1"}',
    ],
)
def test_anything_but_a_beat_is_refused(text: str) -> None:
    assert Beat.decode(text) is None


@pytest.mark.parametrize("args", [["--silence", "0"], ["--silence", "-1"], ["--actions", "navigate_to_pose"]])
def test_the_command_refuses_bad_options_before_starting_ros(args: list[str]) -> None:
    from pmk_nb.cli import main

    with pytest.raises(SystemExit, match="goal-watchdog"):
        main(["robot", "goal-watchdog", *args])


def test_a_beat_survives_its_wire_format() -> None:
    beat = Beat("pmk-tablet-1", True, 2, 17)
    assert Beat.decode(beat.encode()) == beat


# -- the link's heartbeat against the simulator ---------------------------------------------------
class Listener:
    """A second rosbridge client on the heartbeat topic: what the chair's watchdog would hear."""

    def __init__(self, ros: Any) -> None:
        import roslibpy

        self.beats: list[tuple[float, Beat]] = []
        self.lock = threading.Lock()
        self.topic = roslibpy.Topic(ros, TOPIC, "std_msgs/String")
        self.topic.subscribe(self._on)  # roslibpy's I/O thread: store only

    def _on(self, msg: dict) -> None:
        beat = Beat.decode(msg["data"])
        if beat is not None:
            with self.lock:
                self.beats.append((time.monotonic(), beat))

    def since(self, t: float) -> list[Beat]:
        with self.lock:
            return [b for at, b in self.beats if at >= t]


@pytest.mark.slow
@pytest.mark.parametrize("ros", ["ros2", "ros1"])  # Nav2 action; move_base actionlib (std_msgs/String per version)
def test_beats_while_a_goal_runs_then_idle_then_silence(sim_factory, link_factory, ros_factory, ros: str) -> None:
    sim = sim_factory(ros=ros, start_pose=START)
    link = link_factory(sim)
    listener = Listener(ros_factory(sim))
    time.sleep(0.3)  # the subscription is in place before the first beat
    handle = link.navigate_to(*FAR)
    assert wait_until(lambda: handle.progress().status is GoalStatus.MOVING, 10.0)
    t0 = time.monotonic()
    time.sleep(2.0)
    beats = listener.since(t0)
    assert 2 * RATE_HZ - 1 <= len(beats) <= 2 * RATE_HZ + 2, beats  # 2 Hz
    assert all(b.active and b.goals == 1 for b in beats)
    assert len({b.client for b in beats}) == 1 and beats[0].client == heartbeat.for_link(link).client
    handle.cancel()
    assert handle.wait(3.0).status is GoalStatus.CANCELLED
    t1 = time.monotonic()
    assert wait_until(lambda: any(not b.active for b in listener.since(t1)), 1.0), "no idle beat"
    time.sleep(1.5)
    quiet = time.monotonic()
    time.sleep(1.0)
    assert listener.since(quiet) == []  # then silence: nothing left to watch
    assert not heartbeat.for_link(link).active


@pytest.mark.slow
def test_beats_stop_when_the_link_drops_and_the_watch_trips(sim_factory, ros_factory) -> None:
    """A tablet off the network (a frozen proxy: no FIN, no RST): the watchdog hears silence and trips."""
    from pmk_nb.chair.link.client import ChairLink

    sim = sim_factory(ros="ros2", start_pose=START)
    proxy = FreezableProxy(sim.port)
    link = ChairLink("127.0.0.1", proxy.port)
    try:
        link.connect(timeout=10.0)
        listener = Listener(ros_factory(sim))
        watch = GoalWatch(3.0)
        time.sleep(0.3)
        handle = link.navigate_to(*FAR)
        assert wait_until(lambda: len(listener.since(0)) >= 2, 3.0)
        for _, beat in listener.beats:
            watch.beat(beat)
        assert watch.armed == (heartbeat.for_link(link).client,)
        proxy.freeze()
        frozen = time.monotonic()
        time.sleep(0.3)  # a beat already in flight may still land
        fed = len(listener.beats)
        trips: list[Trip] = []
        while not trips and time.monotonic() - frozen < 5.0:
            with listener.lock:
                new, fed = listener.beats[fed:], len(listener.beats)
            for _, beat in new:
                watch.beat(beat)
            trips = watch.tick()
            time.sleep(0.05)
        assert trips, f"no trip within 5 s of the freeze; beats after it: {listener.since(frozen + 0.3)}"
        assert time.monotonic() - frozen <= 3.0 + 1.0
        assert listener.since(frozen + 0.3) == []
        assert handle.progress().status is not GoalStatus.ARRIVED
    finally:
        link.close()
        proxy.close()


@pytest.mark.slow
def test_closing_the_link_mid_goal_stops_the_beats_without_idle(sim_factory, link_factory, ros_factory) -> None:
    """A dashboard that lets go of a running goal (its kernel closes the link) leaves nobody watching:
    no "idle" (that would disarm the watchdog), just silence."""
    sim = sim_factory(ros="ros2", start_pose=START)
    link = link_factory(sim)
    listener = Listener(ros_factory(sim))
    time.sleep(0.3)
    link.navigate_to(*FAR)
    assert wait_until(lambda: len(listener.since(0)) >= 2, 3.0)
    link.close()
    closed = time.monotonic()
    time.sleep(1.5)
    assert [b for b in listener.since(closed) if not b.active] == []
    assert listener.since(closed + 0.3) == []


def test_the_watchdog_takes_a_dashboards_repeated_stop_as_one_press() -> None:
    """A dashboard repeats its Stop for STOP_REPEAT_S (a bridge's new publisher meets the watchdog only
    after discovery); each repeat still cancels, but the log says one press per dashboard and window."""
    from pmk_nb.goalbeat import STOP_REPEAT_S
    from pmk_nb.robot.goalwatch import StopDebounce

    clock = VirtualClock(start=100.0)
    stops = StopDebounce(clock=clock)
    assert stops.admit("page-a")
    clock.advance(STOP_REPEAT_S / 2)
    assert not stops.admit("page-a") and stops.admit("page-b")  # a repeat; another dashboard's own press
    clock.advance(STOP_REPEAT_S + 0.6)
    assert stops.admit("page-a")  # a new press after the window
