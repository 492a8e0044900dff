"""The kernel manager Voilà runs for the dashboard: a kernel lives exactly as long as its page.

Voilà's own ``beforeunload`` beacon is not enough: a tablet that sleeps, a browser that is killed or
a reload that races the beacon leaves a kernel running the live view for ever (idle culling never
sees it idle, and the server buffers its output).  Here the server itself watches each kernel's
websocket connections:

  * a kernel whose last page connection closed is shut down after :data:`PAGE_GRACE` seconds
    (a reload reconnects within that time only if it is the same page; a new page has a new kernel);
  * a kernel whose page never connected is shut down after :data:`FIRST_PAGE_WITHIN` seconds
    (Voilà starts the kernel before the page's websocket exists, so this must allow a slow page load).

A websocket that dies without closing (Wi-Fi gone, tablet asleep) may stay "connected" here for
a long time (the server's websocket pings, :data:`WS_PING_INTERVAL_MS`, time out but the close does
not always complete).  That case is caught by the kernel itself: its page heartbeat stops and it
closes the app, so the live view stops and the chair link closes (:mod:`pmk_nb.ui.page_lifecycle`);
the quiet kernel is then culled as idle.  (A kernel ending its own process while its websocket is
half open made Voilà 0.5 spin at 50 % CPU and stop answering: the kernel does not exit itself.)
"""

from __future__ import annotations

import time
from typing import Any

from jupyter_server.services.kernels.kernelmanager import AsyncMappingKernelManager
from tornado.ioloop import PeriodicCallback

PAGE_GRACE = 3.0
FIRST_PAGE_WITHIN = 120.0
CHECK_INTERVAL_MS = 1000
WS_PING_INTERVAL_MS = 1000
WS_PING_TIMEOUT_MS = 4000


class PageBoundKernelManager(AsyncMappingKernelManager):
    """``AsyncMappingKernelManager`` that shuts a kernel down once no page is connected to it."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._alone_since: dict[str, float] = {}  # kernel id -> when it last had no page
        self._had_page: set[str] = set()
        self._checker: PeriodicCallback | None = None

    async def start_kernel(self, **kwargs: Any) -> str:  # type: ignore[override]
        kernel_id = await super().start_kernel(**kwargs)
        self._alone_since[kernel_id] = time.monotonic()
        if self._checker is None:
            self._checker = PeriodicCallback(self.reap, CHECK_INTERVAL_MS)
            self._checker.start()
        return kernel_id

    def notify_connect(self, kernel_id: str) -> None:
        super().notify_connect(kernel_id)
        self._had_page.add(kernel_id)
        self._alone_since.pop(kernel_id, None)

    def notify_disconnect(self, kernel_id: str) -> None:
        super().notify_disconnect(kernel_id)
        if self._kernel_connections.get(kernel_id, 1) <= 0:
            self._alone_since[kernel_id] = time.monotonic()

    def orphans(self, now: float) -> list[str]:
        """Kernels whose page is gone (or never came) for longer than their grace."""
        return [
            kid
            for kid, since in self._alone_since.items()
            if now - since > (PAGE_GRACE if kid in self._had_page else FIRST_PAGE_WITHIN)
        ]

    async def reap(self) -> None:
        """Shut down the kernels whose page is gone."""
        for kernel_id in self.orphans(time.monotonic()):
            self._alone_since.pop(kernel_id, None)
            self._had_page.discard(kernel_id)
            if kernel_id in self:
                await self._end(kernel_id, "its page is gone", now=False)
        for kernel_id in [k for k in self._alone_since if k not in self]:  # shut down elsewhere
            self._alone_since.pop(kernel_id, None)
            self._had_page.discard(kernel_id)

    async def _end(self, kernel_id: str, why: str, *, now: bool) -> None:
        self.log.info("Kernel %s: %s; shutting it down", kernel_id, why)
        self._alone_since.pop(kernel_id, None)
        self._had_page.discard(kernel_id)
        try:
            await self.shutdown_kernel(kernel_id, now=now)
        except Exception:  # a kernel that refuses to die must not stop the checker
            self.log.exception("shutting down kernel %s failed", kernel_id)
