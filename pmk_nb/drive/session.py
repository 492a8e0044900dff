"""A drive session: the gate, a lock, and the publisher thread that sends what the gate decides.

The thread ticks at :data:`DEFAULT_RATE` (20 Hz: within the 10-20 Hz a base controller expects,
and a release reaches the chair within one 50 ms tick); a press that starts or ends ticks it at
once (the first command leaves as soon as the page's message is in, not up to a tick later). It is
bounded (one thread per session, joined on close) and never runs in a roslibpy callback: publishing
only hands a message to the link's I/O loop. Messages from the page arrive on the kernel's main
thread (a widget change); both sides take the lock for microseconds only.

From a notebook::

    link = get_link("127.0.0.1", 9090); link.connect(); link.start_streams()
    drive_for(link, 0.3, 0.0, seconds=2.0)      # 2 s ahead at 0.3 m/s, then one zero

or, to steer from your own loop (call ``push`` at least every 0.2 s or the chair stops)::

    with DriveSession(link) as drive:
        for v, w in plan:
            drive.push(v, w); time.sleep(0.1)
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from typing import Protocol

from pmk_nb.clock import MONOTONIC, Clock
from pmk_nb.drive.claim import ClaimView, DriveClaim, Hold
from pmk_nb.drive.gate import DriveGate, GateTiming, StopReason
from pmk_nb.drive.limits import SpeedLimits
from pmk_nb.drive.stick import StickEvent, StickMessageError, parse_stick_message

log = logging.getLogger(__name__)
DEFAULT_RATE = 20.0  # Hz
#: Seconds between ticks while the gate is idle (nothing driving, no zero owed): the tick then only
#: refreshes the claim's view (a file read; the page shows it a few times a second) and its 1 s
#: heartbeat.  Every input that gives the gate something to send wakes the thread at once.  Ten
#: classroom pages each read their claim file 20 times a second for nothing (bench/soak_classroom.py).
IDLE_PERIOD_S = 0.25
MIN_RATE, MAX_RATE = 10.0, 50.0
_BLOCKED = {Hold.OTHER_DRIVER: StopReason.OTHER_DRIVER, Hold.STOPPED_ELSEWHERE: StopReason.STOPPED_ELSEWHERE}


class OdometryLike(Protocol):
    @property
    def received(self) -> float: ...  # time.monotonic() when the link got it (read-only: frozen messages)


class DriveLink(Protocol):
    """What a session needs of :class:`pmk_nb.chair.link.client.ChairLink`."""

    @property
    def is_connected(self) -> bool: ...

    def latest_odom(self) -> OdometryLike | None: ...

    def publish_cmd_vel(self, v: float, w: float, topic: str | None = None) -> bool: ...


class DriveSession:
    """Feeds the gate and publishes its decisions on a thread; a context manager.

    Args:
        link: the chair link (connected, streams started: odometry proves the link is fresh).
        limits: the profile's speed limits.
        topic: the profile's velocity topic (None: the link's default, ``/cmd_vel``).
        rate: publisher ticks per second (10 to 50).
        on_stop: called with the reason when the gate stops the chair; runs on the publisher
            thread, so it must be quick.
        clock: the session's time and waits (:mod:`pmk_nb.clock`; a ``VirtualClock`` in tests), the
            same seconds as the odometry's ``received``.
        claim: this page's handle on the chair's shared drive state (one driver per chair, the
            chair-wide Stop); None for a script that is the only driver it knows of.
        stop_goals: what Stop calls to end navigation goals (issue 38: zero velocity does not stop
            a goal, its controller keeps publishing), with the velocity topic; default the link's
            ``stop_goals`` (``ChairLink.stop_goals``) when it has one.
    """

    def __init__(
        self,
        link: DriveLink,
        limits: SpeedLimits | None = None,
        *,
        topic: str | None = None,
        rate: float = DEFAULT_RATE,
        timing: GateTiming | None = None,
        on_stop: Callable[[StopReason], None] | None = None,
        clock: Clock = MONOTONIC,
        claim: DriveClaim | None = None,
        stop_goals: Callable[[str | None], object] | None = None,
    ) -> None:
        if not MIN_RATE <= rate <= MAX_RATE:
            raise ValueError(f"rate must be {MIN_RATE:g} to {MAX_RATE:g} Hz, got {rate!r}")
        self.link, self.topic, self.period = link, topic, 1.0 / rate
        self.gate = DriveGate(limits, timing)
        self.on_stop = on_stop
        self.invalid = 0
        self._stops_reported = 0
        self.last_error: StickMessageError | None = None
        self._clock = clock
        self.claim = claim
        self.stop_goals = stop_goals if stop_goals is not None else getattr(link, "stop_goals", None)
        #: the shared state at the latest tick (None without a claim, or before the first tick)
        self.claim_view: ClaimView | None = None
        self._claim_error: OSError | None = None
        self._lock = threading.Lock()
        self._stop = threading.Event()
        #: set when a press starts or ends: the publisher ticks at once instead of at its next tick
        self._kick = threading.Event()
        self._thread: threading.Thread | None = None

    # -- lifecycle -------------------------------------------------------------------------------
    def start(self) -> DriveSession:
        if self._thread is None or not self._thread.is_alive():
            self._stop = threading.Event()
            self._thread = threading.Thread(target=self._run, args=(self._stop,), name="pmk-drive", daemon=True)
            self._thread.start()
        return self

    def close(self) -> None:
        """Stop the chair (one zero, sent from here) and end the thread."""
        with self._lock:
            if self.gate.driving:
                self.gate.stop(StopReason.CLOSED)
            pending = self.gate.tick(self._clock.now(), True)  # the zero still owed, sent right here
        self._stop.set()
        self._kick.set()
        thread, self._thread = self._thread, None
        if thread is not None and thread is not threading.current_thread():
            thread.join(2.0)
        if pending is not None:
            self._publish(0.0, 0.0)
        if self.claim is not None:
            try:
                self.claim.leave()
            except OSError as err:  # its heartbeat stops anyway: gone after a few seconds
                log.warning("leaving the drive claim %s failed: %s", self.claim.path, err)

    def __enter__(self) -> DriveSession:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- inputs ------------------------------------------------------------------------------------
    @property
    def driving(self) -> bool:
        return self.gate.driving

    @property
    def slow(self) -> bool:
        return self.gate.slow

    @slow.setter
    def slow(self, value: bool) -> None:
        with self._lock:
            self.gate.slow = bool(value)

    def set_limits(self, limits: SpeedLimits) -> None:
        with self._lock:
            self.gate.limits = limits

    def feed(self, text: object) -> StickEvent | None:
        """One message from the page; an invalid one is counted and ignored (never raises)."""
        now = self._clock.now()
        try:
            event = parse_stick_message(text)
        except StickMessageError as err:
            self.invalid += 1
            self.last_error = err
            return None
        with self._lock:
            was = self.gate.driving
            self.gate.on_event(event, now, self._admit if self.claim is not None else None)
            changed = self.gate.driving != was
        if changed:  # a press starts (or ends): its first command (or zero) goes now, not up to a tick later
            self._kick.set()
        return event

    def push(self, v: float, w: float) -> bool:
        """Drive at (v, w) from Python; repeat within 0.2 s (the same deadman as the page).

        False once the chair was stopped (Stop, stale link, a late push): call :meth:`release`
        before driving again.
        """
        with self._lock:
            was = self.gate.driving
            ok = self.gate.on_twist(v, w, self._clock.now(), self._admit if self.claim is not None else None)
            changed = self.gate.driving != was
        if changed:  # the first command goes now, not at the next (idle, slower) tick
            self._kick.set()
        return ok

    def release(self) -> None:
        with self._lock:
            self.gate.release()
            owed = not self.gate.idle
        if owed:  # the zero goes now
            self._kick.set()

    def stop(self) -> None:
        """The Stop button: one zero at the next tick, this press drives no more, (with a claim) the
        chair-wide latch stops every other page's session at its next tick and refuses goals until
        released here, and every navigation goal is cancelled (:attr:`stop_goals`; the other pages'
        kernels cancel theirs when they see the latch: :mod:`pmk_nb.drive.stopwatch`)."""
        with self._lock:
            self.gate.stop(StopReason.STOP_BUTTON)
        if self.claim is not None:  # the latch first: a page ticking after this zero sees it
            try:
                self.claim_view = self.claim.stop()
            except OSError:
                log.exception("latching the Stop for the other pages failed")
        self._kick.set()  # the zero goes now, not at the next (idle, slower) tick
        if self.stop_goals is not None:
            try:
                self.stop_goals(self.topic)
            except Exception:  # the zero and the latch are out; say so, never raise from Stop
                log.exception("cancelling the navigation goals failed")

    def take_over(self) -> ClaimView | None:
        """The explicit take-over: this page becomes the driver (the other page stops at its next tick)."""
        if self.claim is not None:
            self.claim_view = self.claim.take_over()
        return self.claim_view

    def release_stop(self, *, force: bool = False) -> ClaimView | None:
        """Release this page's Stop latch (``force``: also one whose page is gone; an explicit action)."""
        if self.claim is not None:
            self.claim_view = self.claim.release_stop(force=force)
        return self.claim_view

    # -- the claim -----------------------------------------------------------------------------------
    def _admit(self) -> StopReason | None:
        """A press is about to drive (under the lock): this page's own Stop is released by it, a free
        chair is claimed; any other state refuses the press."""
        claim = self.claim
        if claim is None:
            return None
        try:
            view = claim.view()
            if view.hold is Hold.STOPPED_HERE:
                view = claim.release_stop()
            if view.hold is Hold.FREE:
                view = claim.acquire()
        except OSError as err:
            self._claim_failed(err)
            return StopReason.NO_CLAIM
        self.claim_view, self._claim_error = view, None
        return None if view.hold is Hold.MINE else _BLOCKED.get(view.hold, StopReason.OTHER_DRIVER)

    def _claim_failed(self, err: OSError) -> None:
        """Logged once per failure, not at every tick; nothing drives meanwhile."""
        self.claim_view = None
        if self._claim_error is None:
            log.error("the drive claim %s cannot be read or written: %s", getattr(self.claim, "path", "?"), err)
        self._claim_error = err

    def _blocked(self) -> StopReason | None:
        """At a tick: why this session may not go on driving (the heartbeat is written here too)."""
        claim = self.claim
        if claim is None:
            return None
        try:
            view = self.claim_view = claim.view()
        except OSError as err:
            self._claim_failed(err)
            return StopReason.NO_CLAIM
        self._claim_error = None
        # FREE too: this press was admitted, and nobody else holds the chair (a read before the admit)
        return None if view.hold in (Hold.MINE, Hold.FREE) else _BLOCKED.get(view.hold, StopReason.STOP_BUTTON)

    # -- the publisher -----------------------------------------------------------------------------
    def link_ok(self, now: float) -> bool:
        """Connected and odometry younger than the gate's ``odom_fresh``."""
        try:
            if not self.link.is_connected:
                return False
            odom = self.link.latest_odom()
        except Exception:  # a link that fails to answer is not a link to drive through
            log.exception("reading the link state failed")
            return False
        return odom is not None and now - odom.received <= self.gate.timing.odom_fresh

    def _run(self, stop: threading.Event) -> None:
        next_t = self._clock.now()
        while not stop.is_set():
            now = self._clock.now()
            ok = self.link_ok(now)
            blocked = self._blocked()
            with self._lock:
                if blocked is not None and self.gate.driving:
                    self.gate.stop(blocked)
                twist = self.gate.tick(now, ok)
            if twist is not None and not self._publish(*twist) and twist != (0.0, 0.0):
                with self._lock:
                    self.gate.stop(StopReason.LINK)
            self._report_stop()
            period = max(self.period, IDLE_PERIOD_S) if self.gate.idle else self.period
            next_t = max(next_t + period, self._clock.now())
            if self._clock.wait(self._kick, max(0.0, next_t - self._clock.now())):
                self._kick.clear()
                next_t = self._clock.now()  # the kicked tick starts the schedule anew

    def _report_stop(self) -> None:
        count, cause = self.gate.stop_count, self.gate.last_stop
        if count == self._stops_reported or cause is None:
            return
        self._stops_reported = count
        if self.on_stop is not None:
            try:
                self.on_stop(cause)
            except Exception:  # a UI bug must not stop the publisher
                log.exception("drive on_stop callback failed")

    def _publish(self, v: float, w: float) -> bool:
        try:
            return bool(self.link.publish_cmd_vel(v, w, self.topic))
        except Exception:
            log.exception("publishing a velocity command failed")
            return False


def drive_for(
    link: DriveLink,
    v: float,
    w: float,
    seconds: float,
    *,
    limits: SpeedLimits | None = None,
    topic: str | None = None,
    claim: DriveClaim | None = None,
    clock: Clock = MONOTONIC,
) -> StopReason | None:
    """Drive at (v, w) for ``seconds`` (blocking), then stop; returns why it stopped early, or None.

    The same gate as the joystick: limits apply, and a stale link stops the chair at once. With a
    ``claim`` (e.g. ``DriveClaim(config_dir() / "drive", host, port)``) it drives only when no
    dashboard page does, and a Stop on any page stops it.
    """
    with DriveSession(link, limits, topic=topic, claim=claim, clock=clock) as session:
        deadline = clock.now() + max(0.0, seconds)
        session.push(v, w)
        while clock.now() < deadline:
            clock.sleep(min(0.05, max(0.0, deadline - clock.now())))
            if not session.driving or not session.push(v, w):
                return session.gate.last_stop
        session.release()
        clock.sleep(2 * session.period)  # the zero goes out from the thread
    return None
