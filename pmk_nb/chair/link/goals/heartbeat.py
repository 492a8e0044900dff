"""The goal heartbeat: while a goal of this link runs, a beat every 0.5 s on ``/pmk/goal_heartbeat``.

Why: a bridge may keep a lost client's goals alive (the official ROS 2 rosbridge does), so the
chair's goal watchdog (``pmk robot goal-watchdog``) cancels navigation goals when the beats stop.
They stop exactly when nobody can watch: the link dropped, the link was closed, the process died.
When the link's last goal ends, an explicit "idle" beat disarms the watchdog (no cancel of a goal
that finished). The wire format is :mod:`pmk_nb.goalbeat`.

Beats go out from one daemon thread per link, never from roslibpy's I/O thread (where goal updates
arrive: the update callback only stores and wakes the thread). Nothing is queued while the socket
is down: a burst of stale beats after a reconnect would tell the watchdog a lie.

They travel on a second websocket of their own (:func:`side_channel.side_connect`, same URL and
trust as the link), not the link's: rosbridge_suite 2.x with its default
``send_action_goals_in_new_thread:=false`` handles a connection's messages behind that connection's
running goal, so beats sent on the link would wait until the goal ended and the watchdog, hearing
nothing, would cancel every goal after 3 s. They are sent only while the link itself is connected:
the beats vouch for the dashboard's link, not for the second socket.
"""

from __future__ import annotations

import itertools
import json
import logging
import os
import socket
import threading
import uuid
import weakref
from typing import TYPE_CHECKING

from websockets.exceptions import WebSocketException

from pmk_nb.chair.link.transport.side_channel import SIDE_ERRORS, side_connect
from pmk_nb.clock import MONOTONIC, Clock
from pmk_nb.goalbeat import RATE_HZ, TOPIC, Beat
from pmk_nb.wire import spell_type

if TYPE_CHECKING:
    from websockets.sync.client import ClientConnection

    from pmk_nb.chair.link.core import LinkCore
    from pmk_nb.chair.link.goals.goal import GoalHandle, GoalProgress

BEAT_ERRORS: tuple[type[BaseException], ...] = (*SIDE_ERRORS, WebSocketException)

LOG = logging.getLogger(__name__)
IDLE_BEATS = 2  # "idle" twice, a beat apart: one lost message must not leave the watchdog armed

_BEATS: weakref.WeakKeyDictionary[LinkCore, GoalHeartbeat] = weakref.WeakKeyDictionary()
_BEATS_LOCK = threading.Lock()


def client_id() -> str:
    """Names this dashboard in the beats (and so in the watchdog's log): host, process, a random tail."""
    return f"pmk-{socket.gethostname()}-{os.getpid()}-{uuid.uuid4().hex[:6]}"


class GoalHeartbeat:
    """The beats of one link: active while any goal it tracks is not done, then "idle", then silence.

    ``clock`` paces the beats (a ``VirtualClock`` in tests: the beats of a span are exactly counted).
    """

    def __init__(
        self,
        link: LinkCore,
        topic: str = TOPIC,
        rate_hz: float = RATE_HZ,
        client: str | None = None,
        *,
        clock: Clock = MONOTONIC,
    ):
        self._link = weakref.ref(link)
        self._clock = clock
        self.topic, self.period = topic, 1.0 / rate_hz
        self.client = client or client_id()
        self._lock = threading.Lock()
        self._wake = threading.Event()
        self._goals: set[int] = set()
        self._keys = itertools.count(1)
        self._idle_left = 0
        self._seq = itertools.count()
        self._thread: threading.Thread | None = None
        self._ws: ClientConnection | None = None  # the beats' own websocket (beat thread only)
        self.sent: list[Beat] = []  # the beats that reached the socket (the last 20), for tests and logs

    @property
    def active(self) -> bool:
        with self._lock:
            return bool(self._goals)

    def track(self, handle: GoalHandle) -> None:
        """Beat "active" until ``handle`` is done (any terminal state)."""
        with self._lock:
            key = next(self._keys)
            self._goals.add(key)
            self._idle_left = 0
            self._ensure_thread()
            self._wake.set()  # the first beat now, not half a period later (once: the loop clears it)

        def on_update(progress: GoalProgress) -> None:  # roslibpy's I/O thread: store and wake only
            if progress.done:
                self._finished(key)

        handle.on_update(on_update)
        if handle.progress().done:  # finished before the callback was in place
            self._finished(key)

    def _finished(self, key: int) -> None:
        with self._lock:
            if key not in self._goals:
                return
            self._goals.discard(key)
            if not self._goals:
                self._idle_left = IDLE_BEATS
            self._wake.set()

    def _ensure_thread(self) -> None:  # under self._lock
        if self._thread is None or not self._thread.is_alive():
            self._thread = threading.Thread(target=self._run, name="pmk-goal-heartbeat", daemon=True)
            self._thread.start()

    def _run(self) -> None:
        try:
            self._beat_loop()
        finally:
            self._close_socket()

    def _beat_loop(self) -> None:
        while True:
            with self._lock:
                self._wake.clear()  # a wake before this beat is answered by it, not by a second one
                link = self._link()
                if link is None or link.ros is None:  # the link is gone or closed: nobody watches any more
                    self._goals.clear()
                    self._idle_left = 0
                if not self._goals and self._idle_left <= 0:
                    self._thread = None
                    return
                if not self._goals:
                    self._idle_left -= 1
                beat = Beat(self.client, bool(self._goals), len(self._goals), next(self._seq))
            if link is not None:
                self._send(link, beat)
            del link  # no strong reference while waiting: a dropped link can be collected
            self._clock.wait(self._wake, self.period)

    def _send(self, link: LinkCore, beat: Beat) -> None:
        ros = link.ros
        if ros is None or not ros.is_connected:  # the link dropped: silence is the message
            self._close_socket()
            return
        try:
            if self._ws is None:
                self._ws = side_connect(link, timeout=self.period)
                kind = spell_type("std_msgs/String", link.ros_version)
                self._ws.send(json.dumps({"op": "advertise", "topic": self.topic, "type": kind}))
            self._ws.send(json.dumps({"op": "publish", "topic": self.topic, "msg": {"data": beat.encode()}}))
        except BEAT_ERRORS:  # the next beat opens a new socket
            LOG.debug("goal heartbeat not sent", exc_info=True)
            self._close_socket()
            return
        self.sent = [*self.sent[-19:], beat]

    def _close_socket(self) -> None:
        ws, self._ws = self._ws, None
        if ws is not None:
            try:
                ws.close()
            except BEAT_ERRORS:
                pass


def for_link(link: LinkCore) -> GoalHeartbeat:
    """The one heartbeat of ``link`` (made on first use)."""
    with _BEATS_LOCK:
        beat = _BEATS.get(link)
        if beat is None:
            beat = _BEATS[link] = GoalHeartbeat(link)
        return beat


def track(link: LinkCore, handle: GoalHandle) -> None:
    """Beat for ``handle`` on ``link`` until it is done (the hook in :func:`navigate.navigate`)."""
    for_link(link).track(handle)
