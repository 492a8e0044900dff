"""A dashboard kernel served by Voilà lives only as long as its page: heartbeat, watchdog, reload.

A page that closes, reloads, sleeps or loses its websocket must not leave a kernel that keeps the
live view running and a connection to the chair open (issue 10: orphans ran for ever, Voilà buffered
their output).  Three parts:

  * **page -> kernel pings**: a hidden ``ipywidgets.Play`` counts in the browser every
    :data:`PING_INTERVAL_MS`; each count reaches the kernel as a widget update.  No custom
    JavaScript widget is needed (the timer lives in Play's browser-side model).
  * **the kernel's watchdog**: when pings stop for :data:`PAGE_GONE_AFTER` s (or never start
    within :data:`FIRST_PING_WITHIN` s), it closes the app: the live view stops, the chair link
    closes and the kernel falls quiet (no output for Voilà to buffer), to be culled as idle.  This
    catches the websocket that dies without closing (tablet asleep, Wi-Fi gone), which the server
    may not see; a page that closes is shut down by the server within seconds
    (:mod:`pmk_nb.cli.voila_kernels`).
  * **kernel -> page pongs**: every ping is answered by changing a hidden element; a visible,
    online page that sees no pong for :data:`RELOAD_AFTER_MS` reloads itself and so gets a new
    kernel (a kiosk tablet that slept comes back working).

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
FIRST_PING_WITHIN = 120.0
KICK_EVERY = 2.0
RELOAD_AFTER_MS = 15000
PONG_CLASS = "pmk-page-pong"


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
        clock: monotonic seconds (tests pass a fake and call :meth:`check` themselves).
    """

    def __init__(self, on_gone: Callable[[], None], *, clock: Callable[[], float] = time.monotonic) -> None:
        self._on_gone = on_gone
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

    def _watch(self) -> None:
        while not self._stop.wait(1.0):
            if self.check():
                return

    def close(self) -> None:
        """Stop the watchdog (the app is closing anyway)."""
        self._stop.set()


def reload_script() -> str:
    """The page side of the pong: reload a visible, online page whose kernel stopped answering."""
    return f"""<script>
(function () {{
  if (window.__pmkPageWatch) return;
  window.__pmkPageWatch = true;
  var last = null, seen = Date.now(), changes = 0;
  function fresh() {{ seen = Date.now(); }}
  document.addEventListener('visibilitychange', fresh);
  window.addEventListener('online', fresh);
  setInterval(function () {{
    var el = document.querySelector('.{PONG_CLASS}');
    if (!el) return;
    var text = el.textContent;
    if (text !== last) {{ if (last !== null) changes++; last = text; fresh(); return; }}
    if (changes > 0 && document.visibilityState === 'visible' && navigator.onLine
        && Date.now() - seen > {RELOAD_AFTER_MS}) {{
      window.__pmkPageWatch = false;
      location.reload();
    }}
  }}, 1000);
}})();
</script>"""


def attach(app: Any) -> PageWatch | None:
    """Bind ``app``'s kernel to its page when served by Voilà; display the heartbeat and the reload script.

    Returns the :class:`PageWatch`, or None outside Voilà (JupyterLab, tests).
    """
    if not page_bound():
        return None
    from IPython.display import HTML, display

    watch = PageWatch(app.close)
    display(watch.widget)
    display(HTML(f"<div class='pmk-page-watch' style='display:none'></div>{reload_script()}"))
    watch.start()
    return watch
