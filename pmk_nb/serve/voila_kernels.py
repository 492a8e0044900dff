"""The kernel manager Voilà runs for the dashboard: a kernel lives exactly as long as its page.

Voilà's own ``beforeunload`` beacon is not enough: a tablet that sleeps, a browser that is killed or
a reload that races the beacon leaves a kernel running the live view for ever (idle culling never
sees it idle, and the server buffers its output).  Here the server itself watches each kernel's
websocket connections:

  * a kernel whose last page connection closed is shut down after :data:`PAGE_GRACE` seconds when the
    page closed it (a reload reconnects within that time only if it is the same page; a new page has a
    new kernel), after :data:`RECONNECT_GRACE` seconds when the page did not say goodbye (no close
    code: the server gave up on its pings, the network dropped): a live page on a starved machine
    answered a websocket ping too late, lost its socket and reconnected to a kernel already ended;
  * a kernel whose page never connected (closed while it loaded, or a reload that raced it) is shut
    down some time after Voilà finished running the notebook in it (it stops its execution client
    then, and sends the page's last HTML); the page connects once its scripts have loaded.  That time is
    :data:`RENDERED_PAGE_WITHIN` seconds, or :data:`SLOW_CONNECT_FACTOR` times the slowest recent
    page's wait, or as long as its own render took (a page rendered slowly on a loaded machine loads its
    scripts slowly too: the classroom soak at load 20-30 ended pages 20 s after a long render, still
    loading), whichever is longer, at most :data:`FIRST_PAGE_WITHIN` (make soak, 10 pages on 2 cores for
    30 min: 114 pages connected a median 3.0 s, at most 7.2 s, after the render; timed from the
    kernel's own "idle" instead, some took over 20 s and lost their kernel while loading).  While Voilà
    still runs the notebook for the page (its request open, waiting for the HTML) the kernel is never
    taken for orphaned before :data:`RENDERING_LIMIT` seconds: the classroom page's kernel starts its
    own chair, and a fixed 120 s from the kernel's start ended renders still running at load 26.

A websocket that stays alive without the page in it (tablet asleep, page frozen: the browser still
answers the server's websocket pings) stays "connected" here.  That case is caught by the kernel:
its page heartbeat stops, it closes the app (the live view stops, the chair link closes) and sends
:data:`~pmk_nb.ui.common.page_lifecycle.PAGE_GONE_MSG` on IOPub, which this manager listens for and
answers by shutting the kernel down (:mod:`pmk_nb.ui.common.page_lifecycle`).  (A kernel ending its own
process while its websocket is half open made Voilà 0.5 spin at 50 % CPU and stop answering: the
kernel does not exit itself, the server ends it.)

Every page visit also leaves Voilà reference cycles (the rendered notebook, widget state, message
dicts) that only a full garbage collection frees, and Python runs one rarely.  Between them the
garbage of many pages piles up in pymalloc's arenas, which then stay half used and never shrink: the
server grew 1-2 MB per page visit (20 pages: +33-44 MB; allocated blocks stayed flat, arenas
61 -> 76).  The reaper therefore collects after pages come or go, at most every
:data:`COLLECT_EVERY` seconds (20 pages in Chromium: +9 MB, flat after the first round).
"""

from __future__ import annotations

import asyncio
import ctypes
import gc
import time
from typing import Any

from jupyter_client.session import Session
from jupyter_server.services.kernels.kernelmanager import AsyncMappingKernelManager
from tornado.ioloop import IOLoop, PeriodicCallback

from pmk_nb.seams import kernel_connections
from pmk_nb.ui import PAGE_GONE_MSG

PAGE_GRACE = 3.0
RECONNECT_GRACE = 12.0  # a socket closed without the page's goodbye: its page may reconnect
GOODBYE_CODES = (1000, 1001)  # websocket close codes a page sends when it closes or leaves
FIRST_PAGE_WITHIN = 120.0  # the longest wait for a page after its render
RENDERING_LIMIT = 900.0  # a render still running after this long is taken for stuck
RENDERED_PAGE_WITHIN = 20.0  # seconds after the render, at least
SLOW_CONNECT_FACTOR = 3.0
CONNECT_MEMORY = 600.0  # seconds: how long a page's slow connection lengthens the grace of the next ones
CHECK_INTERVAL_MS = 1000
WS_PING_INTERVAL_MS = 1000
WS_PING_TIMEOUT_MS = 4000
COLLECT_EVERY = 2.0


class PageBoundKernelManager(AsyncMappingKernelManager):
    """``AsyncMappingKernelManager`` that shuts a kernel down once no page is connected to it."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)  # type: ignore[no-untyped-call]  # jupyter_server: unannotated
        self._alone_since: dict[str, float] = {}  # kernel id -> when it last had no page
        self._had_page: set[str] = set()
        self._rendered_at: dict[str, float] = {}  # kernel id -> when Voilà finished running it, until a page came
        self._render_took: dict[str, float] = {}  # kernel id -> seconds from its start to the render's end
        self._left_grace: dict[str, float] = {}  # kernel id -> the grace after its page's socket closed
        self._connect_waits: list[tuple[float, float]] = []  # (when, seconds from render to page connection)
        self._checker: PeriodicCallback | None = None
        self._gone_streams: dict[str, Any] = {}  # kernel id -> IOPub stream watched for PAGE_GONE_MSG
        self._ending: dict[str, asyncio.Future[None]] = {}  # shutdowns under way (not awaited by the reaper)
        self._churned = False  # a page or kernel came or went since the last garbage collection
        self._collected_at = 0.0
        self._frozen = False

    async def start_kernel(self, **kwargs: Any) -> str:  # type: ignore[override]
        kernel_id = await super().start_kernel(**kwargs)
        self._alone_since[kernel_id] = time.monotonic()
        self._listen_for_page_gone(kernel_id)
        self._watch_render(kernel_id)
        self._churned = True
        if self._checker is None:
            self._checker = PeriodicCallback(self.reap, CHECK_INTERVAL_MS)
            self._checker.start()
        return kernel_id

    def _listen_for_page_gone(self, kernel_id: str) -> None:
        """Shut the kernel down as soon as it says its page is gone (a silent, still-open websocket)."""
        kernel = self.get_kernel(kernel_id)
        stream: Any = kernel.connect_iopub()  # a ZMQStream (jupyter_client's hints say a socket)
        session = Session(config=kernel.session.config, key=kernel.session.key)
        marker = f'"{PAGE_GONE_MSG}"'.encode()

        def on_iopub(frames: list[Any]) -> None:
            _idents, fed = session.feed_identities(frames, copy=False)
            header: Any = fed[1] if len(fed) >= 2 else None  # a zmq.Frame (copy=False)
            if header is None or marker not in header.bytes:  # the header frame: cheap test first
                return
            try:
                msg_type = session.deserialize(fed, content=False, copy=False)["header"]["msg_type"]
            except Exception:
                return
            if msg_type == PAGE_GONE_MSG:
                IOLoop.current().add_callback(self._start_ending, kernel_id, "its page stopped answering")

        stream.on_recv(on_iopub, copy=False)
        self._gone_streams[kernel_id] = stream

    def _watch_render(self, kernel_id: str) -> None:
        """Note when Voilà stops the client it ran the notebook with: the page's HTML is out then.

        (The kernel's own "idle" comes earlier: on a loaded server Voilà read its output 10 s and more
        later, and pages still loading lost their kernel.)"""
        kernel = self.get_kernel(kernel_id)
        make_client = kernel.client

        def client(**kwargs: Any) -> Any:
            kc = make_client(**kwargs)
            stop = kc.stop_channels

            def stop_channels() -> None:
                stop()
                if kernel_id in self._alone_since and kernel_id not in self._had_page:
                    now = time.monotonic()
                    self._rendered_at[kernel_id] = now
                    self._render_took[kernel_id] = now - self._alone_since[kernel_id]

            kc.stop_channels = stop_channels  # type: ignore[method-assign]  # this one client, on purpose
            return kc

        kernel.client = client  # type: ignore[method-assign]  # this one kernel's, on purpose

    def _forget(self, kernel_id: str) -> None:
        self._alone_since.pop(kernel_id, None)
        self._had_page.discard(kernel_id)
        self._rendered_at.pop(kernel_id, None)
        self._render_took.pop(kernel_id, None)
        self._left_grace.pop(kernel_id, None)
        stream = self._gone_streams.pop(kernel_id, None)
        if stream is not None and not stream.closed():
            stream.close()

    def notify_connect(self, kernel_id: str) -> None:
        super().notify_connect(kernel_id)  # type: ignore[no-untyped-call]  # jupyter_server: unannotated
        if kernel_id not in self._had_page and kernel_id in self._rendered_at:
            now = time.monotonic()
            waited = now - self._rendered_at[kernel_id]
            self._connect_waits = [w for w in self._connect_waits if now - w[0] <= CONNECT_MEMORY] + [(now, waited)]
            self.log.info("Kernel %s: its page connected %.1f s after the render", kernel_id, waited)
        self._had_page.add(kernel_id)
        self._alone_since.pop(kernel_id, None)
        self._rendered_at.pop(kernel_id, None)
        self._churned = True  # the page's render is done: its garbage can go

    def socket_closed(self, kernel_id: str, close_code: int | None) -> None:
        """The page's socket closed with ``close_code`` (None: no close frame from the page): the grace
        before its kernel ends, if no other socket is left (called just before :meth:`notify_disconnect`)."""
        self._left_grace[kernel_id] = PAGE_GRACE if close_code in GOODBYE_CODES else RECONNECT_GRACE
        self.log.info("Kernel %s: its page's socket closed (code %s)", kernel_id, close_code)

    def notify_disconnect(self, kernel_id: str) -> None:
        super().notify_disconnect(kernel_id)  # type: ignore[no-untyped-call]  # jupyter_server: unannotated
        if kernel_connections(self, kernel_id) <= 0:
            self._alone_since[kernel_id] = time.monotonic()
        self._churned = True

    def orphans(self, now: float) -> list[str]:
        """Kernels whose page is gone (or never came) for longer than their grace."""

        def orphaned(kid: str, since: float) -> bool:
            if kid in self._had_page:
                return now - since > self._left_grace.get(kid, PAGE_GRACE)
            rendered = self._rendered_at.get(kid)
            if rendered is None:  # Voilà is still running the notebook for its page
                return now - since > RENDERING_LIMIT
            return now - rendered > self.render_grace(now, self._render_took.get(kid, 0.0))

        return [kid for kid, since in self._alone_since.items() if orphaned(kid, since)]

    def render_grace(self, now: float, render_took: float = 0.0) -> float:
        """Seconds a page may take to connect after its kernel's render: longer while pages load slowly,
        and at least as long as the render took (``render_took``)."""
        recent = [waited for when, waited in self._connect_waits if now - when <= CONNECT_MEMORY]
        slow = max(SLOW_CONNECT_FACTOR * max(recent, default=0.0), render_took)
        return min(max(RENDERED_PAGE_WITHIN, slow), FIRST_PAGE_WITHIN)

    async def reap(self) -> None:
        """Start shutting down the kernels whose page is gone; returns at once.

        A graceful shutdown takes seconds each on a loaded server, and the periodic reaper waits for
        its callback: awaiting them here held every later page's kernel back (make soak: kernels left
        30 s after their pages closed)."""
        for kernel_id in self.orphans(time.monotonic()):
            self._start_ending(kernel_id, "its page is gone")
        known = set(self._alone_since) | set(self._gone_streams)
        for kernel_id in [k for k in known if k not in self and k not in self._ending]:  # culled, API
            self._forget(kernel_id)
        self.collect_garbage(time.monotonic())

    def collect_garbage(self, now: float) -> bool:
        """A full collection when pages came or went, at most every :data:`COLLECT_EVERY` s (see above)."""
        if not self._churned or now - self._collected_at < COLLECT_EVERY:
            return False
        self._churned = False
        self._collected_at = now
        started = time.perf_counter()
        freed = gc.collect()
        trim_heap()  # message buffers are malloc'd: give the pages freed between them back
        if not self._frozen:  # Voilà's modules and templates are loaded by now: later collections skip them
            gc.freeze()
            self._frozen = True
        self.log.debug("garbage collection: %d objects in %.0f ms", freed, 1000 * (time.perf_counter() - started))
        return True

    def _start_ending(self, kernel_id: str, why: str) -> None:
        if kernel_id in self._ending:
            return
        task = asyncio.ensure_future(self._end(kernel_id, why, now=False))
        self._ending[kernel_id] = task
        task.add_done_callback(lambda _t: self._ended(kernel_id))

    def _ended(self, kernel_id: str) -> None:
        self._ending.pop(kernel_id, None)
        self._churned = True

    async def _end(self, kernel_id: str, why: str, *, now: bool) -> None:
        self._forget(kernel_id)
        if kernel_id not in self:
            return
        self.log.info("Kernel %s: %s; shutting it down", kernel_id, why)
        try:
            await self.shutdown_kernel(kernel_id, now=now)  # type: ignore[no-untyped-call]  # jupyter_server: unannotated
        except Exception:  # a kernel that refuses to die must not stop the checker
            self.log.exception("shutting down kernel %s failed", kernel_id)


def trim_heap() -> bool:
    """``malloc_trim(0)``: glibc keeps freed pages inside its heap, and a server whose websocket
    buffers come and go at 40 Hz frees them in scattered places (False where there is no glibc)."""
    try:
        return bool(ctypes.CDLL("libc.so.6").malloc_trim(0) >= 0)
    except (OSError, AttributeError):
        return False
