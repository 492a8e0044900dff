"""Home's status changes for screen readers: a polite and an assertive ``aria-live`` region.

What a sighted rider reads on the map ("Arrived at Storage", "Laser blind ahead", the chair link
lost) a screen-reader user must hear without moving the focus (WCAG 2.2, 4.1.3 Status Messages).
Two visually hidden HTML widgets carry the latest message each: ``role="status"`` /
``aria-live="polite"`` for news (goal set, arrived, link back), ``role="alert"`` /
``aria-live="assertive"`` for safety (Stop, laser blind or something touching ahead, link lost).

An ipywidgets HTML view replaces its content's ``innerHTML`` on each change, so a region written
in the value's markup would be a NEW element each time, which screen readers often do not
announce.  The region is therefore the widget's stable content element: :data:`A11Y_SCRIPT` (run
once per page from an Output, like the joystick's script) gives every ``.pmk-live-polite`` /
``.pmk-live-assertive`` content element its role and ``aria-live`` as soon as it appears.  The
same script frees the keyboard from ipycanvas's canvas, which takes every key, Tab included.

Messages come from any thread (the drive's stop callback runs on its publisher thread): they are
queued under a lock and written by :meth:`Announcer.tick` on Home's info timer.
"""

from __future__ import annotations

import collections
import html
import threading
from typing import Any, Literal

import ipywidgets as w
from IPython.display import HTML

from pmk_nb.speech import phrases
from pmk_nb.ui.home.info import laser_alerts

Urgency = Literal["polite", "assertive"]
POLITE_CLASS = "pmk-live-polite"
ASSERTIVE_CLASS = "pmk-live-assertive"
SR_ONLY_CLASS = "pmk-sr-only"  # visually hidden, still read (pmk_nb/ui/common/a11y_style.py)
MAX_PENDING = 16  # a burst beyond this keeps the newest: old news is no news

#: What the chair link's states are called when they change (Home's info panel shows the same).
LINK_WORDS: dict[str, tuple[str, Urgency]] = {
    "live": ("Chair connected: live view.", "polite"),
    "connecting": ("Connecting to the chair.", "polite"),
    "off": ("Preview stopped.", "polite"),
    "stale": ("No data from the chair.", "assertive"),
    "unreachable": ("The chair is unreachable.", "assertive"),
}
#: A laser alert appearing (see :func:`pmk_nb.ui.home.info.laser_alerts`) is said once.
LASER_WORDS: dict[str, str] = {
    "blind": "Laser blind ahead.",
    "touching": "Something is touching the chair ahead.",
}

A11Y_SCRIPT = f"""<script>
(() => {{
  if (window.__pmkA11y) return;
  window.__pmkA11y = true;
  const regions = [[".{POLITE_CLASS} > .widget-html-content", "status", "polite"],
                   [".{ASSERTIVE_CLASS} > .widget-html-content", "alert", "assertive"]];
  const mark = () => {{
    for (const [selector, role, live] of regions) {{
      for (const el of document.querySelectorAll(selector)) {{
        if (el.getAttribute("aria-live") === live) continue;
        el.setAttribute("role", role);
        el.setAttribute("aria-live", live);
        el.setAttribute("aria-atomic", "true");
      }}
    }}
  }};
  // ipycanvas makes its canvas a tab stop that swallows every key, Tab too (preventDefault in its
  // keydown handler): a keyboard trap (WCAG 2.1.2). The live view reads no key, so the canvas
  // leaves the tab order, and a Tab pressed on a clicked canvas never reaches its handler.
  const untrap = () => {{
    for (const c of document.querySelectorAll(".pmk-app canvas[tabindex='0']")) c.setAttribute("tabindex", "-1");
  }};
  window.addEventListener("keydown", (e) => {{
    if (e.key === "Tab" && e.target instanceof HTMLCanvasElement && e.target.closest(".pmk-app")) {{
      e.stopPropagation();
    }}
  }}, true);
  mark();
  untrap();
  new MutationObserver(() => {{ mark(); untrap(); }}).observe(document.body, {{childList: true, subtree: true}});
}})();
</script>"""


def urgency(phrase: tuple[str, str]) -> Urgency:
    """Assertive for safety (a stop, the link lost), polite for everything else."""
    if phrase[0] == phrases.STOP or phrase == phrases.connection_lost():
        return "assertive"
    return "polite"


class Announcer:
    """The two live regions (``widget``, visually hidden) and what goes into them.

    Feed it with :meth:`phrase` (the speech phrases: goals, arrivals, stops; any thread) and
    :meth:`tick` (the link state and the laser scan on Home's info timer, which also writes).
    """

    def __init__(self) -> None:
        self.polite = w.HTML("")
        self.polite.add_class(POLITE_CLASS)
        self.assertive = w.HTML("")
        self.assertive.add_class(ASSERTIVE_CLASS)
        self.script = w.Output()
        self.script.append_display_data(HTML(A11Y_SCRIPT))
        self.widget = w.Box([self.polite, self.assertive, self.script])
        self.widget.add_class(SR_ONLY_CLASS)
        self.widget.add_class("pmk-live-regions")
        self.said: list[tuple[str, Urgency]] = []  # every message written, for tests and logs
        self._pending: collections.deque[tuple[str, Urgency]] = collections.deque(maxlen=MAX_PENDING)
        self._lock = threading.Lock()
        self._link: str | None = None
        self._alerts: frozenset[str] = frozenset()
        self._seq = 0

    def say(self, text: str, level: Urgency = "polite") -> None:
        """Queue ``text`` (any thread); written on the next :meth:`tick`."""
        if text:
            with self._lock:
                self._pending.append((text, level))

    def phrase(self, phrase: tuple[str, str]) -> None:
        """A speech phrase ``(key, text)`` of :mod:`pmk_nb.speech.phrases`; the link's own are left to
        :meth:`tick` (it says every state, not only lost and back)."""
        if phrase[0] != phrases.LINK:
            self.say(phrase[1], urgency(phrase))

    def tick(self, link_state: str | None = None, scan: Any = None, alerts: frozenset[str] | None = None) -> None:
        """Note a changed link state and new laser alerts, then write what waits (the timer's thread).

        ``alerts`` are Home's own (:attr:`pmk_nb.ui.home.info.InfoTexts.alerts`, read with the map), so
        what is said is what the panel shows; without them they are read from ``scan`` alone."""
        if link_state is not None and link_state != self._link:
            first, self._link = self._link is None, link_state
            words = LINK_WORDS.get(link_state)
            if words is not None and not (first and link_state == "off"):
                self.say(*words)
        if alerts is None:
            alerts = laser_alerts(scan)
        if link_state != "live":
            alerts = frozenset()
        for alert in sorted(alerts - self._alerts):
            self.say(LASER_WORDS[alert], "assertive")
        self._alerts = alerts
        self.flush()

    def flush(self) -> None:
        """Write the newest pending message of each urgency (older ones of a burst are dropped)."""
        with self._lock:
            pending = list(self._pending)
            self._pending.clear()
        for level, region in (("polite", self.polite), ("assertive", self.assertive)):
            texts = [t for t, lv in pending if lv == level]
            if not texts:
                continue
            text = " ".join(dict.fromkeys(texts[-2:]))  # a burst: the last two, each once
            self._seq += 1
            region.value = f"<p data-seq='{self._seq}'>{html.escape(text)}</p>"
            self.said.append((text, level))  # type: ignore[arg-type]
