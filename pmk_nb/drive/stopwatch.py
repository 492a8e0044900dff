"""Every page's eye on the chair-wide Stop, for navigation goals (issue 38, item 1).

The stick is checked against the Stop latch at every tick of a :class:`~pmk_nb.drive.session.DriveSession`,
but a goal runs without one: page A's "Go to" drove the chair on after page B's Stop. A
:class:`StopWatch` runs in every page's kernel while its live view has a chair link (the Drive panel
need not be open): it reads the chair's claim file (:class:`~pmk_nb.drive.claim.DriveClaim`, read-only)
every :data:`POLL_S` and, when another page latches a Stop (a new ``stop_at``), calls ``on_stop``
(the dashboard's: ``ChairLink.stop_goals``: cancel this kernel's goals, cancel all natively, zero).
The page that pressed Stop cancels in :meth:`DriveSession.stop` itself; its watch skips its own latch.

It is also the goal gate: :meth:`latched_at` reads the file now and gives the latched Stop's wall time
(``ChairLink.goal_gate``): no goal leaves while a Stop is latched on any page.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable

from pmk_nb.drive.claim import ClaimView, DriveClaim

log = logging.getLogger(__name__)
POLL_S = 0.1


class StopWatch:
    """Watches one chair's Stop latch on a daemon thread; ``start()``, ``close()``.

    Args:
        claim: this page's handle on the chair's shared state (the Drive panel's member, so that
            its own latch is known as its own); only read here.
        on_stop: called on the watch's thread when another page latches a Stop; must not block long.
        The polls wait on the claim's clock (``DriveClaim.clock``: a ``VirtualClock`` in tests).
    """

    def __init__(self, claim: DriveClaim, on_stop: Callable[[], object], poll: float = POLL_S) -> None:
        self.claim, self.on_stop, self.poll = claim, on_stop, poll
        self.view: ClaimView | None = None  # the latest read (None before the first, or unreadable)
        self.fired = 0  # how many latches ``on_stop`` answered
        self._seen: float | None = None
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def start(self) -> StopWatch:
        if self._thread is None:
            self._thread = threading.Thread(target=self._run, name="pmk-stop-watch", daemon=True)
            self._thread.start()
        return self

    def close(self) -> None:
        self._stop.set()
        thread, self._thread = self._thread, None
        if thread is not None and thread is not threading.current_thread():
            thread.join(2.0)

    def latched_at(self) -> float | None:
        """The wall time of the Stop latched for this chair now (any page's), else None; an unreadable
        claim file counts as latched (now): a goal must not leave when nobody can tell."""
        try:
            view = self.claim.peek()
        except OSError as err:
            log.warning("the Stop latch %s cannot be read: %s", self.claim.path, err)
            return self.claim.clock.now()
        return view.stop_at

    @property
    def latched(self) -> bool:
        """A Stop was latched at the latest read (for the buttons; the gate reads the file itself)."""
        view = self.view
        return view is not None and view.stop_at is not None

    def tick(self) -> None:
        """One read; ``on_stop`` for a latch of another page not answered yet."""
        try:
            view = self.view = self.claim.peek()
        except OSError as err:
            self.view = None
            log.debug("the Stop latch %s cannot be read: %s", self.claim.path, err)
            return
        if view.stop_at is None or view.stop_at == self._seen:
            return
        self._seen = view.stop_at
        if view.stop_by_me:
            return  # this page's own Stop cancelled its goals when it was pressed
        self.fired += 1
        try:
            self.on_stop()
        except Exception:  # a failing cancel must not end the watch
            log.exception("cancelling the goals after another page's Stop failed")

    def _run(self) -> None:
        while not self._stop.is_set():
            self.tick()
            self.claim.clock.wait(self._stop, self.poll)
