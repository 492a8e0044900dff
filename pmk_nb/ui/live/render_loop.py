"""A frame clock that calls a draw step at most N times per second, decoupled from message rates.

In a kernel (JupyterLab or Voilà, ipykernel >= 6) cells and widget callbacks run inside the
kernel's asyncio loop on the main thread, so the loop is an asyncio task there: drawing then happens
on the same thread as every other widget call, between messages, and never races with them.
Outside a running loop (plain Python, pytest, a CLI) it falls back to a daemon thread; drawing from
that thread is safe for ipycanvas as long as only the loop draws (the live view holds a lock).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import threading
from collections.abc import Callable

from pmk_nb.clock import MONOTONIC, AsyncPacer, Clock
from pmk_nb.ui.common.page_lifecycle import page_can_draw

log = logging.getLogger(__name__)

MIN_FPS = 1.0
MAX_FPS = 60.0


def running_loop() -> asyncio.AbstractEventLoop | None:
    """The asyncio loop running in this thread (the kernel's), or None."""
    try:
        return asyncio.get_running_loop()
    except RuntimeError:
        return None


class RenderLoop:
    """Call ``step()`` at most ``fps`` times a second until :meth:`stop`.

    Args:
        step: draws one frame; its exceptions are counted, never propagated; the first of a run
            of failing steps is logged with its traceback.
        fps: frame-rate cap, clamped to 1..60.
        on_error: called with the exception when a step fails (e.g. to show it in the UI).
        max_errors: consecutive failing steps after which the loop stops itself.
        ready: a tick draws only while this says True; default :func:`page_lifecycle.page_can_draw`
            (on a Voilà page: not before the page's first heartbeat, or Voilà would buffer every
            frame drawn before the page's websocket exists).
        clock: the pacing's time and its waits, in either mode (a ``VirtualClock`` in tests:
            the frames in a span of virtual time are exactly counted).
    """

    def __init__(
        self,
        step: Callable[[], object],
        fps: float = 20.0,
        *,
        on_error: Callable[[BaseException], None] | None = None,
        max_errors: int = 20,
        ready: Callable[[], bool] = page_can_draw,
        clock: Clock = MONOTONIC,
    ) -> None:
        self._step = step
        self._clock = clock
        self._ready = ready
        self.fps = fps
        self._on_error = on_error
        self._max_errors = max(1, int(max_errors))
        self._stop = threading.Event()
        self._task: asyncio.Task[None] | None = None
        self._task_loop: asyncio.AbstractEventLoop | None = None
        self._thread: threading.Thread | None = None
        self._consecutive_errors = 0
        self.ticks = 0
        self.mode: str | None = None

    @property
    def fps(self) -> float:
        return self._fps

    @fps.setter
    def fps(self, value: float) -> None:
        try:
            fps = float(value)
        except (TypeError, ValueError) as err:
            raise ValueError(f"fps must be a number, got {value!r}") from err
        if fps != fps:  # NaN
            raise ValueError("fps must be a number, got NaN")
        self._fps = min(max(fps, MIN_FPS), MAX_FPS)

    @property
    def running(self) -> bool:
        """True from start() until stop() (or the loop gave up after too many failing frames)."""
        if self._stop.is_set():
            return False
        if self._task is not None:
            return not self._task.done()
        return self._thread is not None and self._thread.is_alive()

    def start(self, *, prefer: str = "auto") -> str:
        """Start ticking (no-op if already running); returns the mode: "asyncio" or "thread".

        ``prefer="thread"`` forces the thread mode (e.g. for a benchmark driving its own loop).
        """
        if self.running:
            return self.mode or ""
        self._stop = threading.Event()
        self._consecutive_errors = 0
        loop = running_loop() if prefer != "thread" else None
        if loop is not None:
            self._task_loop = loop
            self._task = loop.create_task(self._run_async(self._stop))
            self._thread = None
            self.mode = "asyncio"
        else:
            self._task = None
            self._thread = threading.Thread(
                target=self._run_thread, args=(self._stop,), name="pmk-render-loop", daemon=True
            )
            self._thread.start()
            self.mode = "thread"
        return self.mode

    def stop(self, timeout: float = 2.0) -> None:
        """Stop ticking; waits for the thread (not for an asyncio task, which stops at its next tick)."""
        self._stop.set()
        task, loop, thread = self._task, self._task_loop, self._thread
        if task is not None and loop is not None and not task.done():
            if running_loop() is loop:
                task.cancel()
            elif not loop.is_closed():
                with contextlib.suppress(RuntimeError):
                    loop.call_soon_threadsafe(task.cancel)
        if thread is not None and thread is not threading.current_thread():
            thread.join(timeout)

    def _tick(self, stop: threading.Event) -> None:
        if not self._ready():
            self.ticks += 1
            return
        try:
            self._step()
            self._consecutive_errors = 0
        except Exception as err:
            self._consecutive_errors += 1
            if self._consecutive_errors == 1:  # the traceback once per run of failures, not per frame
                log.exception("render step failed")
            if self._on_error is not None:
                with contextlib.suppress(Exception):
                    self._on_error(err)
            if self._consecutive_errors >= self._max_errors:
                log.error("render loop stopped after %d failing frames", self._consecutive_errors)
                stop.set()
        self.ticks += 1

    def _next(self, next_t: float) -> tuple[float, float]:
        """(delay, deadline) for the next tick.

        A frame a little late (less than a frame period) keeps the schedule, so the average rate
        stays at ``fps`` despite timer jitter; further behind, the schedule restarts instead of
        bursting frames to catch up.
        """
        period = 1.0 / self._fps
        next_t += period
        now = self._clock.now()
        if next_t < now - period:
            next_t = now
        return max(next_t - now, 0.0), next_t

    async def _run_async(self, stop: threading.Event) -> None:
        next_t, pacer = self._clock.now(), AsyncPacer(self._clock)
        try:
            while not stop.is_set():
                self._tick(stop)
                delay, next_t = self._next(next_t)
                # always yield a little so widget messages get handled even when frames run late
                await pacer.sleep(max(delay, 0.002))
        finally:
            pacer.close()

    def _run_thread(self, stop: threading.Event) -> None:
        next_t = self._clock.now()
        while not stop.is_set():
            self._tick(stop)
            delay, next_t = self._next(next_t)
            self._clock.wait(stop, max(delay, 0.001))
