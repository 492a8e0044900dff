"""The goal watchdog's decisions, free of ROS: arm on an "active" beat, disarm on "idle", trip on silence.

``pmk robot goal-watchdog`` (:mod:`pmk_nb.robot.watchdog_ros2`, :mod:`pmk_nb.robot.watchdog_ros1`)
feeds every heartbeat to :meth:`GoalWatch.beat` and calls :meth:`GoalWatch.tick` from a timer; a
:class:`Trip` means "cancel the navigation goals now". Each dashboard (``client``) is armed on its
own: one tablet that finished does not disarm another that still drives. A trip cancels all goals
(the cancel services have no notion of client), once per silence. The clock is injected (:mod:`pmk_nb.clock`) so that
the unit tests advance a ``VirtualClock`` and need no sleeping.
"""

from __future__ import annotations

from dataclasses import dataclass

from pmk_nb.clock import MONOTONIC, Clock
from pmk_nb.goalbeat import SILENCE_S, STOP_REPEAT_S, Beat

READY_LINE = "pmk robot goal-watchdog: ready"


@dataclass(frozen=True)
class Trip:
    """The heartbeat of ``client`` fell silent ``silent_s`` seconds ago while its goals ran."""

    client: str
    silent_s: float
    goals: int


@dataclass(frozen=True)
class Change:
    """What a beat changed: ``armed`` (True: armed now, False: disarmed), for the log."""

    client: str
    armed: bool


class StopDebounce:
    """One cancel-all per Stop: a dashboard repeats its Stop for a while (:data:`STOP_REPEAT_S`), so the
    repeats of one client within that window are the same press."""

    def __init__(self, window_s: float = STOP_REPEAT_S + 0.5, clock: Clock = MONOTONIC) -> None:
        self.window_s = window_s
        self._clock = clock
        self._last: dict[str, float] = {}

    def admit(self, client: str) -> bool:
        """True for a new press of ``client``'s Stop, False for a repeat of the last one."""
        now = self._clock.now()
        last = self._last.get(client)
        self._last[client] = now
        return last is None or now - last > self.window_s


class GoalWatch:
    """Armed clients and when each was last heard. Not thread-safe: call from one thread (the
    node's executor / rospy's timer and subscriber under the node's lock)."""

    def __init__(self, silence_s: float = SILENCE_S, clock: Clock = MONOTONIC) -> None:
        if silence_s <= 0:
            raise ValueError(f"silence_s must be > 0, got {silence_s}")
        self.silence_s = silence_s
        self._clock = clock
        self._armed: dict[str, tuple[float, int]] = {}  # client -> (last heard, goals it had)

    @property
    def armed(self) -> tuple[str, ...]:
        return tuple(self._armed)

    def beat(self, beat: Beat) -> Change | None:
        """Take one heartbeat; returns the change it made (None: nothing changed)."""
        was = beat.client in self._armed
        if beat.active:
            self._armed[beat.client] = (self._clock.now(), beat.goals)
            return None if was else Change(beat.client, True)
        self._armed.pop(beat.client, None)
        return Change(beat.client, False) if was else None

    def tick(self) -> list[Trip]:
        """The clients silent for ``silence_s`` or longer; each trips once and is disarmed."""
        now = self._clock.now()
        trips = [
            Trip(client, now - heard, goals)
            for client, (heard, goals) in self._armed.items()
            if now - heard >= self.silence_s
        ]
        for trip in trips:
            del self._armed[trip.client]
        return trips
