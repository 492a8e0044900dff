"""A dashboard kernel served by Voilà lives only as long as its page: heartbeat, watchdog, reload.

A page that closes, reloads, sleeps or loses its websocket must not leave a kernel that keeps the
live view running and a connection to the chair open (issue 10: orphans ran for ever, Voilà buffered
their output).  Three parts:

  * **page -> kernel pings**: a hidden ``ipywidgets.Play`` counts in the browser every
    :data:`PING_INTERVAL_MS`; each count reaches the kernel as a widget update.  No custom
    JavaScript widget is needed (the timer lives in Play's browser-side model).
  * **the kernel's watchdog**: when pings stop for :data:`PAGE_GONE_AFTER` s (or never start
    within :data:`FIRST_PING_WITHIN` s), it closes the app (the live view stops, the chair link
    closes) and sends the server a :data:`PAGE_GONE_MSG` message on IOPub, on which the server
    shuts the kernel down at once (:mod:`pmk_nb.cli.voila_kernels`).  This catches the websocket
    that stays alive at TCP level while the page sends nothing (tablet asleep, page frozen), which
    the server cannot tell from a quiet page; a page that closes is shut down by the server itself.
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
PAGE_GONE_AFTER = 6.0
FIRST_PING_WITHIN = 300.0  # a loaded server renders slowly; a page that never connects is the server's (120 s)
KICK_EVERY = 2.0
RELOAD_AFTER_MS = 15000
WAKE_GRACE_MS = 6000  # after waking, a live kernel answers within one ping interval (+ a loaded machine)
SLEPT_MS = 20000  # a 1 s page timer that did not run for this long was asleep (shorter: a loaded machine)
RELOAD_MEMORY_MS = 600000  # reloads within this window back the next one off (no reload storm under load)
MAX_RELOAD_WAIT_MS = 300000
PONG_CLASS = "pmk-page-pong"
#: IOPub message type the kernel sends when its page is gone; the server then shuts the kernel down.
PAGE_GONE_MSG = "pmk_page_gone"


_watch: PageWatch | None = None  # this kernel's page watch (one app per Voilà kernel)


def page_ready() -> bool:
    """False on a Voilà page until its first heartbeat: the page can show frames only from then on.

    (Frames drawn before the page's websocket is connected are buffered by Voilà, and under load
    that was hundreds of MB.)  True outside Voilà.
    """
    watch = _watch
    return watch is None or watch.pings > 0


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
        self.play.observe(self._on_ping, names="value")
        self.widget = w.Box([self.play, self.pong], layout=w.Layout(display="none"))
        self._thread = threading.Thread(target=self._watch, name="pmk-page-watchdog", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def _on_ping(self, _change: dict[str, Any]) -> None:
        with self._lock:
            if self.gone:
                return
            self._last_ping = self._clock()
            self.pings += 1
            count = self.pings
        self.pong.value = str(count)

    def page_gone(self, now: float) -> bool:
        """No ping for :data:`PAGE_GONE_AFTER` s, or none at all within :data:`FIRST_PING_WITHIN` s."""
        with self._lock:
            if self._last_ping is None:
                return now - self._started > FIRST_PING_WITHIN
            return now - self._last_ping > PAGE_GONE_AFTER

    def check(self) -> bool:
        """One watchdog step: start the page's timer while no ping came; close once the page is gone."""
        now = self._clock()
        if self.gone:
            return True
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
        while not self._stop.wait(1.0):
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
  var staleAfter = Math.min({RELOAD_AFTER_MS} * Math.pow(2, earlier.length), {MAX_RELOAD_WAIT_MS});
  function woke() {{ wokeAt = Date.now(); }}
  function reload() {{
    try {{ sessionStorage.setItem(KEY, JSON.stringify(earlier.concat([Date.now()]))); }} catch (e) {{}}
    window.__pmkPageWatch = false;
    location.reload();
  }}
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
    if (text !== last) {{ if (last !== null || text !== '0') changes++; last = text; pongAt = now; return; }}
    if (changes === 0 || document.visibilityState !== 'visible' || !navigator.onLine) return;
    var wokeUnanswered = earlier.length === 0 && wokeAt > pongAt && now - wokeAt > {WAKE_GRACE_MS};
    if (wokeUnanswered || now - pongAt > staleAfter) reload();
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
