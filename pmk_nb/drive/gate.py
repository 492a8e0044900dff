"""The deadman: what the dashboard sends at each publisher tick, and when it stops the chair.

Rules (issue 11), in the kernel's monotonic clock:

* a command goes out only while the stick is held and its latest message is fresh;
* release (or Stop) -> one zero command, then silence (the chair's own timeout is not needed);
* a message older than :attr:`GateTiming.max_age` (200 ms) is dropped, never sent: not when it
  arrives late, and not at a tick when the latest one has grown that old;
* no fresh message for :attr:`GateTiming.keepalive_timeout` (300 ms: websocket dropped, kernel busy,
  page frozen) -> one zero, then silence;
* a stale link (not connected, or no odometry for :attr:`GateTiming.odom_fresh`) -> zero, silence;
* a hidden page -> zero, silence.

After Stop or a safety stop the same press never drives again: the user lifts the finger and
presses anew. Late messages of the old press that arrive in a burst (a kernel that was busy)
cannot restart the chair, and neither can a message that names a new page: its current press
counts as stopped too (only a later press drives).

Whether this page may drive at all (one driver per chair, a Stop on another page) is asked of an
``admit`` callback when a press starts (:mod:`pmk_nb.drive.claim` through the session).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum

from pmk_nb.drive.limits import SpeedLimits, stick_to_twist
from pmk_nb.drive.stick import ClockOffset, StickEvent

ZERO = (0.0, 0.0)
#: Asked when a press is about to drive: None to drive, or why not (that press is then over).
Admit = Callable[[], "StopReason | None"]


class StopReason(str, Enum):
    RELEASED = "released"
    STOP_BUTTON = "stop button"
    HIDDEN = "page hidden"
    KEEPALIVE = "no news from the page"
    LINK = "link stale"
    CLOSED = "closed"
    OTHER_DRIVER = "another page drives"  # taken over, or another page held the chair first
    STOPPED_ELSEWHERE = "stopped on another page"  # the chair-wide Stop latch (drive/claim.py)
    NO_CLAIM = "drive claim unreadable"  # the shared state cannot be read: nothing drives


@dataclass(frozen=True)
class GateTiming:
    max_age: float = 0.2  # s: an older command is dropped
    keepalive_timeout: float = 0.3  # s without a fresh message while held -> stop
    odom_fresh: float = 0.35  # s: older odometry means the link is stale


@dataclass
class GateStats:
    sent: int = 0
    zeros: int = 0
    dropped_late: int = 0  # messages that arrived too old
    skipped_ticks: int = 0  # ticks with nothing fresh enough to send
    ignored: int = 0  # duplicates, out of order, or a press that was stopped


class DriveGate:
    """Pure state machine; :class:`~pmk_nb.drive.session.DriveSession` adds the thread and the lock."""

    def __init__(self, limits: SpeedLimits | None = None, timing: GateTiming | None = None) -> None:
        self.limits = limits or SpeedLimits()
        self.timing = timing or GateTiming()
        self.clock = ClockOffset()
        self.slow = False
        self.stats = GateStats()
        self.driving = False
        self.last_stop: StopReason | None = None
        self.stop_count = 0  # stops of a drive (a release counts), for "stopped" feedback
        self._target = ZERO
        self._sent_at = 0.0  # kernel time the latest fresh message was sent
        self._page: str | None = None
        self._seq = -1
        self._press = -1  # the press being driven
        self._stopped_press = -1  # presses up to this one may not drive any more
        self._latched = False  # a stop (not a release) since the last press that drove
        self._zero_pending = False
        self._twist_press: int | None = None  # the press of Python's commands, None when released

    # -- inputs ----------------------------------------------------------------------------------
    def on_event(self, event: StickEvent, now: float, admit: Admit | None = None) -> None:
        """A message from the page (already validated), received at kernel time ``now``."""
        if event.page != self._page:  # a new page load: its own clock and counters
            # after a stop, the new page's current press is over too: a new id is no way around Stop
            self._page, self._seq = event.page, -1
            self._stopped_press = event.press if self._latched else -1
            self.clock.reset()
            if self.driving:
                self._stop(StopReason.RELEASED)
        if event.seq <= self._seq:
            self.stats.ignored += 1
            return
        self._seq = event.seq
        self.clock.observe(now, event.t)
        if event.hidden or not event.held:
            if self.driving:
                self._stop(StopReason.HIDDEN if event.hidden else StopReason.RELEASED)
            return
        if event.press <= self._stopped_press:
            self.stats.ignored += 1
            return
        sent_at = self.clock.kernel_time(event.t)
        if now - sent_at > self.timing.max_age:
            self.stats.dropped_late += 1
            return
        if not (self.driving and event.press == self._press) and self._refused(event.press, admit):
            return
        self._take(event.press, stick_to_twist(event.x, event.y, self.limits, self.slow), sent_at)

    def _refused(self, press: int, admit: Admit | None) -> bool:
        """Ask ``admit`` before a press drives; a refused press is over (a later one may drive)."""
        cause = admit() if admit is not None else None
        if cause is None:
            return False
        self._stopped_press = max(self._stopped_press, press)
        self.stats.ignored += 1
        if self.driving:
            self._stop(cause)
        else:
            self.last_stop = cause
        return True

    def on_twist(self, v: float, w: float, now: float, admit: Admit | None = None) -> bool:
        """A command from Python in the kernel (fresh by construction), clamped to the limits.

        Like a held stick: the first call presses, :meth:`release` lifts; after a stop the calls
        are refused (False) until released.
        """
        if self._twist_press is None:
            self._twist_press = max(self._press, self._stopped_press) + 1
        if self._twist_press <= self._stopped_press:
            self.stats.ignored += 1
            return False
        if not (self.driving and self._twist_press == self._press) and self._refused(self._twist_press, admit):
            return False
        self._take(self._twist_press, self.limits.clamp(v, w, self.slow), now)
        return True

    def release(self) -> None:
        self._twist_press = None
        if self.driving:
            self._stop(StopReason.RELEASED)

    def stop(self, cause: StopReason = StopReason.STOP_BUTTON) -> None:
        """End the drive now (the Stop button): one zero even when not driving, and the press is over."""
        self._stop(cause)

    def _take(self, press: int, twist: tuple[float, float], sent_at: float) -> None:
        self.driving, self._press, self._target, self._sent_at = True, press, twist, sent_at
        self._zero_pending = self._latched = False

    def _stop(self, cause: StopReason) -> None:
        if cause is not StopReason.RELEASED:
            self._stopped_press = max(self._stopped_press, self._press)
            self._latched = True
        if self.driving:
            self.stop_count += 1
        self.driving = False
        self._zero_pending = True
        self.last_stop = cause

    @property
    def idle(self) -> bool:
        """Nothing to send until a new input: not driving, no zero owed (the publisher may tick slowly)."""
        return not self.driving and not self._zero_pending

    # -- the publisher's tick ----------------------------------------------------------------------
    def tick(self, now: float, link_ok: bool) -> tuple[float, float] | None:
        """The twist to publish now, or None for silence."""
        if self.driving:
            if not link_ok:
                self._stop(StopReason.LINK)
            elif now - self._sent_at > self.timing.keepalive_timeout:
                self._stop(StopReason.KEEPALIVE)
            elif now - self._sent_at > self.timing.max_age:
                self.stats.skipped_ticks += 1
                return None
            else:
                self.stats.sent += 1
                return self._target
        if self._zero_pending:
            self._zero_pending = False
            self.stats.zeros += 1
            return ZERO
        return None
