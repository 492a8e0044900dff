"""The goal heartbeat's pacing on virtual time (issue 39): a beat at once, one per 0.5 s while the goal
runs, two "idle" beats a period apart when it ends, then silence; nothing while the link is down.
(The beats against a simulated chair and the watchdog: tests/chair/link/test_goal_watchdog.py.)"""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import Any

import pytest

from pmk_nb.chair.link.goals import heartbeat
from pmk_nb.clock import VirtualClock
from pmk_nb.goalbeat import Beat


class FakeSocket:
    def __init__(self, beats: list[Beat]) -> None:
        self.beats = beats

    def send(self, text: str) -> None:
        message = json.loads(text)
        if message["op"] == "publish":
            self.beats.append(Beat.decode(message["msg"]["data"]))

    def close(self) -> None:
        pass


class FakeRos:
    is_connected = True


class FakeLink:
    ros_version = 2

    def __init__(self) -> None:
        self.ros: Any = FakeRos()


class FakeGoal:
    def __init__(self) -> None:
        self.callbacks: list[Callable[[Any], None]] = []
        self.done = False

    def on_update(self, callback: Callable[[Any], None]) -> None:
        self.callbacks.append(callback)

    def progress(self) -> Any:
        return type("Progress", (), {"done": self.done})()

    def finish(self) -> None:
        self.done = True
        for callback in self.callbacks:
            callback(self.progress())


@pytest.fixture
def beats(monkeypatch: pytest.MonkeyPatch) -> list[Beat]:
    sent: list[Beat] = []
    monkeypatch.setattr(heartbeat, "side_connect", lambda link, timeout: FakeSocket(sent))
    return sent


def test_beats_every_half_second_while_a_goal_runs_then_two_idle_then_silence(beats: list[Beat]) -> None:
    clock, link, goal = VirtualClock(start=0.0), FakeLink(), FakeGoal()
    beat = heartbeat.GoalHeartbeat(link, clock=clock)  # type: ignore[arg-type]
    beat.track(goal)  # type: ignore[arg-type]
    assert clock.wait_for_waiters(1)
    assert [b.active for b in beats] == [True], "the first beat at once"
    clock.advance(2.0)
    assert [b.active for b in beats] == [True] * 5, "one every 0.5 s"
    goal.finish()
    clock.advance(0.0)
    assert [b.active for b in beats] == [True] * 5 + [False], "idle at once when the goal ends"
    clock.advance(0.5)
    assert [b.active for b in beats] == [True] * 5 + [False] * 2
    clock.advance(10.0)
    assert len(beats) == 7 and not beat.active, "then silence"
    assert [b.seq for b in beats] == list(range(7))


def test_no_beat_while_the_link_is_down_and_none_queued_for_later(beats: list[Beat]) -> None:
    clock, link, goal = VirtualClock(start=0.0), FakeLink(), FakeGoal()
    beat = heartbeat.GoalHeartbeat(link, clock=clock)  # type: ignore[arg-type]
    beat.track(goal)  # type: ignore[arg-type]
    assert clock.wait_for_waiters(1)
    link.ros.is_connected = False
    clock.advance(3.0)
    assert len(beats) == 1, "silence is the message while the link is down"
    link.ros.is_connected = True
    clock.advance(0.5)
    assert len(beats) == 2 and beats[-1].active, "the next beat only, no burst of stale ones"
    goal.finish()
    clock.advance(5.0)
