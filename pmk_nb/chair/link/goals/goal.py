"""A goal's types: its status, progress, handle, policy and route; the routes (``goal_routes``,
``goal_topic``), the goal watch and the heartbeat use them without importing :mod:`.navigate`, which
starts a goal through them (no import cycle)."""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from dataclasses import dataclass, replace
from enum import Enum
from typing import TYPE_CHECKING

from pmk_nb.clock import MONOTONIC, Clock
from pmk_nb.errors import ChairLinkError

if TYPE_CHECKING:
    from pmk_nb.chair.link.goals.goal_attach import ActionStatusFollower

LOG = logging.getLogger(__name__)
ARRIVE_TOLERANCE = 0.25  # m: goal-topic route, no action server to say "arrived"


class GoalStatus(str, Enum):
    PENDING = "pending"
    ACCEPTED = "accepted"
    MOVING = "moving"
    ARRIVED = "arrived"
    ABORTED = "aborted"
    CANCELLED = "cancelled"
    REJECTED = "rejected"
    LINK_LOST = "link_lost"  # the link dropped: the chair may still be driving
    NO_ANSWER = "no_answer"  # nothing accepted the goal in time: the chair may have started
    CANCEL_IGNORED = "cancel_ignored"  # odometry shows the chair moving after a cancel
    UNKNOWN = "unknown"  # after the link came back the chair no longer reports the goal


TERMINAL = frozenset(
    {GoalStatus.ARRIVED, GoalStatus.ABORTED, GoalStatus.CANCELLED, GoalStatus.REJECTED, GoalStatus.UNKNOWN}
)
LINK_LOSS_POLICIES = ("finish", "cancel")


@dataclass(frozen=True)
class GoalPolicy:
    """Deadlines and what to do after a link loss (profile fields ``goal_*``; see the README)."""

    accept_s: float = 5.0  # no acceptance within it: no_answer, and a cancel is sent
    quiet_s: float = 30.0  # no result or feedback for this long: said on screen
    verify_s: float = 1.0  # after a cancel odometry must show the chair stopped within it
    on_link_loss: str = "finish"  # "finish": let goals finish; "cancel": cancel them on reconnect


@dataclass(frozen=True)
class GoalProgress:
    """The latest word on a goal: status, the goal (x, y, yaw), metres left (None: not known yet)."""

    status: GoalStatus
    goal: tuple[float, float, float]
    remaining_m: float | None
    message: str
    quiet_s: float | None = None  # no word from the chair for this long (None: recent news)

    @property
    def done(self) -> bool:
        return self.status in TERMINAL


class NavigationError(ChairLinkError):
    """A goal could not be sent (not connected, no route). ``route`` names what was tried."""

    def __init__(self, message: str, *, route: str = "", host: str | None = None, port: int | None = None) -> None:
        super().__init__(message, host=host, port=port)
        self.route = route


UpdateCallback = Callable[[GoalProgress], None]


class GoalHandle:
    """One goal on its way. Thread-safe; a terminal status is final (later updates are ignored).

    ``clock``: the goal's time (sent, last news, cancels) and waits; its goal watch and route poller
    read the same one (a ``VirtualClock`` in tests: deadlines then fall at exact instants).
    """

    def __init__(self, goal: tuple[float, float, float], route: str, *, clock: Clock = MONOTONIC) -> None:
        self.clock = clock
        self.route = route  # which way the goal went; every message starts with it
        self._lock = threading.Lock()
        self._progress = GoalProgress(GoalStatus.PENDING, goal, None, route)
        self._done = threading.Event()
        self._callbacks: list[UpdateCallback] = []
        self._cancel: Callable[[], None] | None = None
        self.cancel_requested = False
        self.sent_at = self.last_news = clock.now()
        self.cancel_at: float | None = None  # the latest cancel (the goal watch verifies it)
        self.cancel_honoured: bool | None = None  # None: not verified (yet)
        self.zero_bursts = 0  # zero-velocity bursts sent because a cancel was not honoured
        self.follower: ActionStatusFollower | None = (
            None  # Nav2: the action's status topic, for re-attaching after a link loss
        )
        self.cancel_ref: tuple[str, str] | None = None  # Nav2: (action, rosbridge goal id)

    def progress(self) -> GoalProgress:
        with self._lock:
            return self._progress

    def cancel(self) -> None:
        """Ask the chair to stop this goal; the status turns ``cancelled`` when the chair confirms.
        Sent again on every call (a Stop pressed twice); the goal watch checks the chair stops."""
        self.cancel_requested = True
        self.cancel_at, self.cancel_honoured = self.clock.now(), None
        cancel = self._cancel
        if cancel is not None and not self._done.is_set():
            cancel()

    def wait(self, timeout: float) -> GoalProgress:
        """Block until the goal is done or ``timeout`` s pass; returns the latest progress either way."""
        self.clock.wait(self._done, timeout)
        return self.progress()

    def on_update(self, cb: UpdateCallback) -> None:
        """``cb(progress)`` on every change, on the thread that saw it (roslibpy's): store only."""
        with self._lock:
            self._callbacks.append(cb)

    # -- for the routes and the goal watch ----------------------------------------------------------
    def bind_cancel(self, fn: Callable[[], None]) -> None:
        self._cancel = fn
        if self.cancel_requested:
            fn()

    def update(
        self,
        status: GoalStatus | None = None,
        remaining: float | None = None,
        text: str | None = None,
        *,
        news: bool = True,
    ) -> None:
        """New status / metres left / text (prefixed with the route); None keeps the old value.

        ``news``: the chair said it (the routes); False for what the goal watch concludes. A chair
        still reporting "moving" does not undo ``cancel_ignored``: it is what that state says.
        """
        with self._lock:
            old = self._progress
            if old.done:
                return
            if news:
                self.last_news = self.clock.now()
            if old.status is GoalStatus.CANCEL_IGNORED and status in (GoalStatus.ACCEPTED, GoalStatus.MOVING):
                status, text = None, None
            new = replace(
                old,
                status=status or old.status,
                remaining_m=remaining if remaining is not None else old.remaining_m,
                message=old.message if text is None else f"{self.route}: {text}",
                quiet_s=None if news else old.quiet_s,
            )
            callbacks = self._store(old, new)
        self._notify(new, callbacks)

    def mark_quiet(self, seconds: float | None) -> None:
        """The goal watch: the chair has said nothing for ``seconds`` (None: clear)."""
        with self._lock:
            old = self._progress
            new = replace(old, quiet_s=seconds)
            callbacks = None if old.done else self._store(old, new)
        self._notify(new, callbacks)

    def _store(self, old: GoalProgress, new: GoalProgress) -> list[UpdateCallback] | None:
        """Keep ``new`` (lock held); the callbacks to run, None when nothing changed."""
        if new == old:
            return None
        self._progress = new
        return list(self._callbacks)

    def _notify(self, new: GoalProgress, callbacks: list[UpdateCallback] | None) -> None:
        if callbacks is None:
            return
        if new.done:
            self._done.set()
        for cb in callbacks:
            try:
                cb(new)
            except Exception:
                LOG.exception("goal update callback failed")


@dataclass(frozen=True)
class GoalRoute:
    """How goals reach this chair: ``kind`` "nav2" | "actionlib" | "topic", the name used, and
    Nav2's NavigateThroughPoses when offered."""

    kind: str
    name: str
    through: str | None = None

    @property
    def label(self) -> str:
        if self.kind == "nav2":
            return f"Nav2 NavigateToPose ({self.name})"
        if self.kind == "actionlib":
            return f"move_base actionlib ({self.name})"
        return f"goal topic {self.name} (progress from the chair's pose)"
