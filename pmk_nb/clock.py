"""Time as an input (issue 39): everything that decides by time takes a :class:`Clock`.

The real one is :class:`MonotonicClock`. Tests pass a :class:`VirtualClock`, whose time moves only
when the test calls :meth:`VirtualClock.advance`: a publisher, a heartbeat or a render loop then
runs exactly the ticks that fall in the advanced span, whatever the machine's load, and a test
asserts exact outcomes ("after 300 ms of silence, one zero and nothing after") instead of rates.
"""

from __future__ import annotations

import asyncio
import heapq
import logging
import queue
import threading
import time
from dataclasses import dataclass, field
from typing import Protocol

log = logging.getLogger(__name__)


class Clock(Protocol):
    """Monotonic seconds, and the two ways code waits on them."""

    def now(self) -> float: ...

    def wait(self, event: threading.Event, timeout: float) -> bool:
        """Block until ``event`` is set (True) or ``timeout`` seconds pass (False, unless set by then)."""
        ...

    def sleep(self, seconds: float) -> None: ...


class MonotonicClock:
    """The real clock: ``time.monotonic`` and the threading primitives' own timeouts."""

    def now(self) -> float:
        return time.monotonic()

    def wait(self, event: threading.Event, timeout: float) -> bool:
        return event.wait(max(0.0, timeout))

    def sleep(self, seconds: float) -> None:
        time.sleep(max(0.0, seconds))


#: the shared real clock (stateless: one is enough)
MONOTONIC = MonotonicClock()


class WallClock(MonotonicClock):
    """Seconds since the epoch, for times other processes read (a seat's start in a shared file, the
    drive claim's beats) and message stamps; waits as the real clock's."""

    def now(self) -> float:
        return time.time()


#: the shared wall clock
WALL = WallClock()


class AsyncPacer:
    """``await pacer.sleep(s)`` on a clock, for one asyncio task (the simulator's loops).

    The real clocks sleep with ``asyncio.sleep``, as before. Any other clock (a ``VirtualClock``) is
    waited on by one thread of the pacer's own, which wakes the task and then holds still until the
    task asks for its next sleep: a ``VirtualClock.advance`` therefore returns only once the task has
    run every step due in the span. One pacer per task; a task cancelled in its sleep closes it (a task
    that ends otherwise calls :meth:`close`, else its thread holds each ``advance`` for its
    ``settle_timeout``).
    """

    def __init__(self, clock: Clock) -> None:
        self.clock = clock
        self._requests: queue.SimpleQueue[tuple[float, asyncio.AbstractEventLoop, asyncio.Future[None]] | None]
        self._requests = queue.SimpleQueue()
        self._closed = threading.Event()
        self._thread: threading.Thread | None = None

    async def sleep(self, seconds: float) -> None:
        if isinstance(self.clock, MonotonicClock):
            await asyncio.sleep(max(0.0, seconds))
            return
        loop = asyncio.get_running_loop()
        woke: asyncio.Future[None] = loop.create_future()
        if self._thread is None:
            self._thread = threading.Thread(target=self._run, name="pmk-pacer", daemon=True)
            self._thread.start()
        self._requests.put((seconds, loop, woke))
        try:
            await woke
        except asyncio.CancelledError:  # the task ends (the simulator stops): so does the thread
            self.close()
            raise

    def close(self) -> None:
        """End the pacer's thread (the task is done): a sleep under way ends at once, unanswered."""
        self._closed.set()
        self._requests.put(None)

    def _run(self) -> None:
        while not self._closed.is_set():
            request = self._requests.get()
            if request is None:
                return
            seconds, loop, woke = request
            if self.clock.wait(self._closed, seconds):
                return
            try:
                loop.call_soon_threadsafe(_wake, woke)
            except RuntimeError:  # the loop is closed: nobody to wake
                return


def _wake(woke: asyncio.Future[None]) -> None:
    if not woke.done():  # the sleeping task may have been cancelled meanwhile
        woke.set_result(None)


#: real seconds between a virtual waiter's looks at its event (``Event.set`` notifies nobody else)
_POLL_S = 0.002


@dataclass(order=True)
class _Waiter:
    deadline: float
    seq: int
    event: threading.Event = field(compare=False)
    thread: threading.Thread = field(compare=False)
    done: bool = field(default=False, compare=False)


class VirtualClock:
    """A clock for tests: time moves only on :meth:`advance`; thread-safe.

    A :meth:`wait` or :meth:`sleep` blocks until virtual time reaches its deadline or its event is
    set. :meth:`advance` moves time from deadline to deadline in order, and at each one lets the
    woken threads run until each is waiting again or has ended, so when it returns every tick due in
    the span has run. A thread that wakes and then blocks on something else for longer than
    ``settle_timeout`` real seconds is no longer waited for (logged), so a test never hangs on it.

    Args:
        start: the initial time (any value: monotonic time has no epoch).
        settle_timeout: real seconds :meth:`advance` waits for a woken thread to settle.
    """

    def __init__(self, start: float = 1000.0, *, settle_timeout: float = 10.0) -> None:
        self._now = float(start)
        self._cond = threading.Condition()
        self._waiters: list[_Waiter] = []  # a heap by deadline
        self._running: dict[threading.Thread, float] = {}  # woken, not waiting again: since (real s)
        self._seq = 0
        self.settle_timeout = settle_timeout

    def now(self) -> float:
        with self._cond:
            return self._now

    def __call__(self) -> float:
        """The clock as a plain ``Callable[[], float]`` for code that only reads the time."""
        return self.now()

    def sleep(self, seconds: float) -> None:
        self.wait(threading.Event(), seconds)

    def wait(self, event: threading.Event, timeout: float) -> bool:
        me = threading.current_thread()
        with self._cond:
            waiter = _Waiter(self._now + max(0.0, timeout), self._seq, event, me)
            self._seq += 1
            heapq.heappush(self._waiters, waiter)
            self._running.pop(me, None)
            self._cond.notify_all()  # an advance waiting for this thread to settle
            try:
                while not event.is_set() and self._now < waiter.deadline:
                    self._cond.wait(_POLL_S)
                return event.is_set()
            finally:
                waiter.done = True
                self._waiters.remove(waiter)
                heapq.heapify(self._waiters)
                self._running[me] = time.monotonic()
                self._cond.notify_all()

    @property
    def waiting(self) -> int:
        """How many waits are blocked now (a test's way to know its thread has started waiting)."""
        with self._cond:
            return len(self._waiters)

    def wait_for_waiters(self, count: int = 1, timeout: float = 10.0) -> bool:
        """Block (real time, up to ``timeout``) until ``count`` waits are blocked: the threads started."""
        with self._cond:
            return self._cond.wait_for(lambda: len(self._waiters) >= count, timeout)

    def advance(self, seconds: float) -> None:
        """Move time by ``seconds``, waking waiters in deadline order and letting each run."""
        if seconds < 0:
            raise ValueError(f"a clock never goes back: advance({seconds!r})")
        with self._cond:
            target = self._now + seconds
            self._settle()
            while self._waiters and self._waiters[0].deadline <= target:
                self._now = max(self._now, self._waiters[0].deadline)
                self._cond.notify_all()
                self._settle()
            self._now = target
            self._cond.notify_all()
            self._settle()

    def _due(self) -> bool:
        return any(w.event.is_set() or w.deadline <= self._now for w in self._waiters)

    def _settle(self) -> None:
        """Under the lock: until no waiter is due and every woken thread waits again or has ended."""
        give_up = time.monotonic() + self.settle_timeout
        while True:
            for thread in [t for t in self._running if not t.is_alive() or t is threading.current_thread()]:
                del self._running[thread]
            if not self._due() and not self._running:
                return
            if time.monotonic() > give_up:
                log.warning("virtual clock: threads that do not settle: %s", [t.name for t in self._running])
                self._running.clear()
                if not self._due():
                    return
                give_up = time.monotonic() + self.settle_timeout
            self._cond.wait(_POLL_S)
