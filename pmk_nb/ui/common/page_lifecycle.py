"""A dashboard kernel served by Voilà lives only as long as its page: heartbeat, watchdog, reload.

A page that closes, reloads, sleeps or loses its websocket must not leave a kernel that keeps the
live view running and a connection to the chair open (issue 10: orphans ran for ever, Voilà buffered
their output).  Three parts:

  * **page -> kernel pings**: a hidden ``ipywidgets.Play`` counts in the browser every
    :data:`PING_INTERVAL_MS`; each count reaches the kernel as a widget update.  No custom
    JavaScript widget is needed (the timer lives in Play's browser-side model).
  * **the kernel's watchdog**: when pings stop for :data:`PAGE_GONE_AFTER` s (or never start
    within :data:`FIRST_PING_WITHIN` s), it closes the app.  A page or kernel that is merely slow
    must not be taken for gone (on a loaded server that fed a storm of reloads and new kernels):
    the deadline grows to :data:`SLOW_FACTOR` times the longest gap between pings of the last
    :data:`SLOW_MEMORY` s (at most :data:`MAX_PAGE_GONE_AFTER` s), and time the watchdog itself was
    held up (the kernel starved of CPU, its pings still queued) does not count.  It then closes the
    app (the live view stops, the chair link closes) and sends the server a :data:`PAGE_GONE_MSG`
    message on IOPub, on which the server shuts the kernel down at once
    (:mod:`pmk_nb.serve.voila_kernels`).  This catches the websocket that stays alive at TCP level
    while the page sends nothing (tablet asleep, page frozen), which the server cannot tell from a
    quiet page; a page that closes is shut down by the server itself.
  * **flow control**: the page writes each pong it has seen into a hidden text widget (the ack).
    A pong sent more than :data:`MAX_BEHIND` s ago and not yet acked means the page is that far
    behind the kernel's output (a loaded tablet or server): the live view sends no frame until it
    has caught up (:func:`page_can_draw`), so frames never pile up in Voilà or the browser, and
    the pongs behind them are not held up for tens of seconds (make soak: pages reloaded in step).
  * **kernel -> page pongs**: every ping is answered by changing a hidden element.  A page that
    wakes (its timer stalled, or ``visibilitychange``/``pageshow``/``resume``/``online``) and sees no
    new pong within :data:`WAKE_GRACE_MS` reloads itself, and so does a visible, online page with no
    pong for :data:`RELOAD_AFTER_MS`: a kiosk tablet that slept comes back working, on a new kernel.
    Each reload within :data:`RELOAD_MEMORY_MS` doubles the wait before the next one (sessionStorage):
    on an overloaded server, reloads that start more kernels must not feed on themselves.

Only pages served by Voilà are bound (``VOILA_SERVER_URL`` in the kernel's environment, or
``PMK_PAGE_BOUND=1``): in JupyterLab the kernel belongs to the notebook, not to one output.
"""

from __future__ import annotations

import logging
import os
import threading
import time
from collections.abc import Callable
from typing import Any

import ipywidgets as w

log = logging.getLogger(__name__)

PAGE_BOUND_ENV = "PMK_PAGE_BOUND"
PING_INTERVAL_MS = 2000
PAGE_GONE_AFTER = 8.0  # seconds without a ping from a page that pinged on time
MAX_PAGE_GONE_AFTER = 20.0  # ... from a page whose pings came late (a loaded tablet or server)
SLOW_FACTOR = 3.0
SLOW_MEMORY = 60.0
FIRST_PING_WITHIN = 300.0  # a loaded server renders slowly; a page that never connects is the server's (120 s)
KICK_EVERY = 2.0
WATCH_EVERY = 1.0  # seconds between watchdog checks
# A server busy starting a page's kernel stops every page's pongs for seconds at a time: pages that
# reloaded after 15 s in step started more kernels and fed a storm (make soak, 150 kernels for 10 pages).
RELOAD_AFTER_MS = 45000  # times 0.75-1.25 at random per page, so pages never reload in step
WAKE_GRACE_MS = 10000  # after waking, a live kernel answers within one ping interval (+ a loaded machine)
SLEPT_MS = 20000  # a 1 s page timer that did not run for this long was asleep (shorter: a loaded machine)
RELOAD_MEMORY_MS = 600000  # reloads within this window back the next one off (no reload storm under load)
MAX_RELOAD_WAIT_MS = 300000
PONG_CLASS = "pmk-page-pong"
ACK_CLASS = "pmk-page-ack"
MAX_BEHIND = 1.5  # seconds: a page further behind the kernel's output gets no new frame
#: IOPub message type the kernel sends when its page is gone; the server then shuts the kernel down.
PAGE_GONE_MSG = "pmk_page_gone"


_watch: PageWatch | None = None  # this kernel's page watch (one app per Voilà kernel)
_LOADED_AT = time.monotonic()
UNWATCHED_GRACE = 30.0  # seconds a Voilà kernel with no page watch waits before connecting anyway


def page_ready() -> bool:
    """False on a Voilà page until its first heartbeat: the page can show frames only from then on.

    (Frames drawn before the page's websocket is connected are buffered by Voilà, and under load
    that was hundreds of MB.)  True outside Voilà.
    """
    watch = _watch
    return watch is None or watch.pings > 0


def page_seen() -> bool:
    """Whether the page has sent its first heartbeat: the chair is connected only then, so a kernel
    whose page closed while loading never holds a chair connection.  A Voilà kernel is built before
    its page watch is attached: until then (at most :data:`UNWATCHED_GRACE` s) it counts as not seen.
    True outside Voilà."""
    watch = _watch
    if watch is not None:
        return watch.pings > 0
    return not page_bound() or time.monotonic() - _LOADED_AT > UNWATCHED_GRACE


def page_can_draw() -> bool:
    """:func:`page_ready`, and the page is keeping up with the kernel's output (see :meth:`PageWatch.behind`)."""
    watch = _watch
    return page_ready() and (watch is None or watch.behind(time.monotonic()) <= MAX_BEHIND)


def page_bound() -> bool:
    """True when this kernel serves one Voilà page (``PMK_PAGE_BOUND`` overrides either way)."""
    forced = os.environ.get(PAGE_BOUND_ENV, "").strip().lower()
    if forced in ("0", "1", "true", "false", "yes", "no", "on", "off"):
        return forced in ("1", "true", "yes", "on")
    return "VOILA_SERVER_URL" in os.environ or "VOILA_BASE_URL" in os.environ


class PageWatch:
    """Heartbeat widgets plus the watchdog thread; ``on_gone`` runs once, on the watchdog thread.

    Args:
        on_gone: what to do when the page is gone (the app's ``close``).
        on_closed: runs after ``on_gone`` (in Voilà: :func:`tell_server_page_gone`).
        clock: monotonic seconds (tests pass a fake and call :meth:`check` themselves).
    """

    def __init__(
        self,
        on_gone: Callable[[], None],
        *,
        clock: Callable[[], float] = time.monotonic,
        on_closed: Callable[[], None] = lambda: None,
    ) -> None:
        self._on_gone = on_gone
        self._on_closed = on_closed
        self._clock = clock
        self._started = clock()
        self._last_ping: float | None = None
        self._last_kick = self._started
        self._last_check = self._started
        self._gaps: list[tuple[float, float]] = []  # (when, seconds since the ping before)
        self._sent: dict[int, float] = {}  # pong value -> when it was sent, until the page acks it
        self.acked = 0
        self.pings = 0
        self.gone = False
        self._stop = threading.Event()
        self._lock = threading.Lock()
        hidden = {"layout": w.Layout(display="none")}
        # playing starts False: Play's browser model only starts its timer on a change to True (see kick)
        self.play = w.Play(value=0, min=0, max=2**31 - 1, step=1, interval=PING_INTERVAL_MS, playing=False, **hidden)
        self.play.add_class("pmk-page-ping")
        self.pong = w.HTML("0", **hidden)
        self.pong.add_class(PONG_CLASS)
        self.ack = w.Text(value="", continuous_update=True, **hidden)
        self.ack.add_class(ACK_CLASS)
        self.play.observe(self._on_ping, names="value")
        self.ack.observe(self._on_ack, names="value")
        self.widget = w.Box([self.play, self.pong, self.ack], layout=w.Layout(display="none"))
        self._thread = threading.Thread(target=self._watch, name="pmk-page-watchdog", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def _on_ping(self, _change: dict[str, Any]) -> None:
        with self._lock:
            if self.gone:
                return
            now = self._clock()
            if self._last_ping is not None:
                self._gaps = [g for g in self._gaps if now - g[0] <= SLOW_MEMORY] + [(now, now - self._last_ping)]
            self._last_ping = now
            self.pings += 1
            count = self.pings
            if self.acked:  # flow control only once the page has shown it acks (its script runs)
                self._sent = {k: t for k, t in self._sent.items() if k > count - 64}
                self._sent[count] = now
        self.pong.value = str(count)

    def _on_ack(self, change: dict[str, Any]) -> None:
        """The page has seen pong ``value`` (a page can send anything: only a pong we sent counts)."""
        try:
            seen = int(str(change.get("new", "")).strip())
        except ValueError:
            return
        with self._lock:
            if not 0 < seen <= self.pings or seen <= self.acked:
                return
            self.acked = seen
            self._sent = {k: t for k, t in self._sent.items() if k > seen}

    def behind(self, now: float) -> float:
        """Seconds since the oldest pong the page has not acked yet was sent (0: it is up to date)."""
        with self._lock:
            return now - min(self._sent.values()) if self._sent else 0.0

    def deadline(self, now: float) -> float:
        """Seconds without a ping after which the page is gone: longer for a page whose pings came late."""
        with self._lock:
            recent = [gap for when, gap in self._gaps if now - when <= SLOW_MEMORY]
        slow = SLOW_FACTOR * max(recent, default=0.0)
        return min(max(PAGE_GONE_AFTER, slow), MAX_PAGE_GONE_AFTER)

    def page_gone(self, now: float) -> bool:
        """No ping for :meth:`deadline` s, or none at all within :data:`FIRST_PING_WITHIN` s."""
        limit = self.deadline(now)
        with self._lock:
            if self._last_ping is None:
                return now - self._started > FIRST_PING_WITHIN
            return now - self._last_ping > limit

    def check(self) -> bool:
        """One watchdog step: start the page's timer while no ping came; close once the page is gone."""
        now = self._clock()
        if self.gone:
            return True
        waited = now - self._last_check
        self._last_check = now
        if waited > 2 * WATCH_EVERY:  # this process was starved: pings may be waiting unread, not missing
            stalled = waited - WATCH_EVERY
            with self._lock:
                if self._last_ping is not None:
                    self._last_ping += stalled
                self._started += stalled
            return False
        if self.page_gone(now):
            self._close_app()
            return True
        if self._last_ping is None and now - self._last_kick >= KICK_EVERY:
            # (re)start Play's timer: the page may have rendered since the last try, or reconnected
            self._last_kick = now
            self.play.playing = False
            self.play.playing = True
        return False

    def _close_app(self) -> None:
        with self._lock:
            if self.gone:
                return
            self.gone = True
        log.info("the page is gone (%d pings): closing the app", self.pings)
        try:
            self._on_gone()
        except Exception:
            log.exception("closing the app after its page went failed")
        finally:
            self._stop.set()
            self._on_closed()

    def _watch(self) -> None:
        while not self._stop.wait(WATCH_EVERY):
            if self.check():
                return

    def close(self) -> None:
        """Stop the watchdog (the app is closing anyway)."""
        self._stop.set()


def reload_script() -> str:
    """The page side of the pong: a page that woke, or whose kernel stopped answering, reloads itself."""
    return f"""<script>
(function () {{
  if (window.__pmkPageWatch) return;
  window.__pmkPageWatch = true;
  var last = null, changes = 0, pongAt = Date.now(), tickAt = Date.now(), wokeAt = 0;
  var KEY = 'pmkPageReloads', earlier = [];
  try {{
    earlier = JSON.parse(sessionStorage.getItem(KEY) || '[]').filter(function (t) {{
      return Date.now() - t < {RELOAD_MEMORY_MS};
    }});
  }} catch (e) {{}}
  var staleAfter = Math.min({RELOAD_AFTER_MS} * (0.75 + 0.5 * Math.random()) * Math.pow(2, earlier.length),
                            {MAX_RELOAD_WAIT_MS});
  function woke() {{ wokeAt = Date.now(); }}
  function reload(why) {{
    console.info('pmk page watch: reloading (' + why + ')');
    try {{ sessionStorage.setItem(KEY, JSON.stringify(earlier.concat([Date.now()]))); }} catch (e) {{}}
    window.__pmkPageWatch = false;
    location.reload();
  }}
  function ack() {{  // tell the kernel which pong this page has seen: its frames wait while we lag
    var el = document.querySelector('.{PONG_CLASS}');
    var box = document.querySelector('.{ACK_CLASS} input, input.{ACK_CLASS}');
    if (!el || !box || box.value === el.textContent) return;
    box.value = el.textContent;
    box.dispatchEvent(new Event('input', {{ bubbles: true }}));
  }}
  setInterval(ack, 200);
  document.addEventListener('visibilitychange', function () {{
    if (document.visibilityState === 'visible') woke();
  }});
  document.addEventListener('resume', woke);
  window.addEventListener('pageshow', woke);
  window.addEventListener('online', woke);
  setInterval(function () {{
    var now = Date.now();
    if (now - tickAt > {SLEPT_MS}) woke();  // this timer stalled: the page slept or was frozen
    tickAt = now;
    var el = document.querySelector('.{PONG_CLASS}');
    var text = el ? el.textContent : last;  // gone with a dead kernel's widgets: as stale as unchanged
    // a pong other than the first "0" proves a kernel answered, even when this script started late
    // (a loaded tablet) and never saw the "0": such a page that then sleeps must reload on waking
    if (text !== last) {{ if (last !== null || text !== '0') changes++; last = text; pongAt = now; ack(); return; }}
    if (changes === 0 || document.visibilityState !== 'visible' || !navigator.onLine) return;
    var wokeUnanswered = earlier.length === 0 && wokeAt > pongAt && now - wokeAt > {WAKE_GRACE_MS};
    if (wokeUnanswered) reload('woke, no answer for ' + (now - wokeAt) + ' ms');
    else if (now - pongAt > staleAfter) reload('no answer for ' + (now - pongAt) + ' ms');
  }}, 1000);
}})();
</script>"""


def tell_server_page_gone() -> None:
    """Send :data:`PAGE_GONE_MSG` on this kernel's IOPub: the Voilà server shuts the kernel down.

    (The kernel does not end its own process: with its websocket half open that made Voilà 0.5 spin.)
    """
    from ipykernel.kernelapp import IPKernelApp

    if not IPKernelApp.initialized():
        return
    kernel = IPKernelApp.instance().kernel
    try:
        kernel.session.send(kernel.iopub_socket, PAGE_GONE_MSG, {}, ident=PAGE_GONE_MSG.encode())
    except Exception:  # the server then culls the quiet kernel as idle, later
        log.exception("could not tell the server that the page is gone")


def attach(app: Any) -> PageWatch | None:
    """Bind ``app``'s kernel to its page when served by Voilà; display the heartbeat and the reload script.

    Returns the :class:`PageWatch`, or None outside Voilà (JupyterLab, tests).
    """
    if not page_bound():
        return None
    from IPython.display import HTML, display

    global _watch
    watch = PageWatch(app.close, on_closed=tell_server_page_gone)
    _watch = watch
    display(watch.widget)
    display(HTML(f"<div class='pmk-page-watch' style='display:none'></div>{reload_script()}"))
    watch.start()
    return watch
