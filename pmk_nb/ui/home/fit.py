"""The map fills the screen: the page tells the kernel how much room the map has and what covers it.

A canvas has a size in pixels that only the kernel sets, and stretching it with CSS would distort
the map, so the page measures and the kernel resizes (issue 28).  A ``<script>`` shown once in a
hidden output (as :mod:`pmk_nb.ui.drive.script` does) watches Home's map box and posts, into the
hidden Text widget ``.pmk-home-fit-channel``, JSON ``{"w", "h", "boxes"}``: the box's width, the
height left in the window below the box's top (so the map takes the rest of the first screen),
and the boxes of the panels floating over the canvas (tool bar, status line, Drive panel) in
canvas pixels.  :class:`FitChannel` checks every field (a page can send anything), resizes the
canvas (:meth:`LiveView.fit_page`) and turns the boxes into the insets the view keeps the chair
clear of (:func:`pmk_nb.viewport.insets_from_boxes`).  It also publishes where the chair is drawn
(``data-x`` / ``data-y`` on ``.pmk-home-chair-at span``, canvas pixels), the canvas size, zoom level
and insets, so the page's tests can work out the view (:func:`tests.page_view.page_view`).
"""

from __future__ import annotations

import json
import logging
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.ui.common.page_numbers import page_number
from pmk_nb.ui.live import canvas_focus
from pmk_nb.viewport import insets_from_boxes

if TYPE_CHECKING:
    from pmk_nb.ui.live.view import LiveView

log = logging.getLogger(__name__)

CHANNEL_CLASS = "pmk-home-fit-channel"
CHAIR_AT_CLASS = "pmk-home-chair-at"
#: what floats over the map and so may cover the chair (the Drive panel only while shown)
OVERLAY_SELECTORS = (".pmk-home-toolbar", ".pmk-home-statusline", ".pmk-drive")
MAX_BOXES = 8
MIN_PX, MAX_PX = 160, 4000
BOTTOM_GAP_PX = 8  # left below the map so the window does not scroll by a pixel

SCRIPT = """<script>
(function () {
  if (window.__pmkFit) return;
  window.__pmkFit = { sent: 0, last: '' };
  var OVER = __OVER__;
  function shown(el) { return el && el.offsetParent !== null && el.getClientRects().length > 0; }
  function docTop(el) {
    var t = el.getBoundingClientRect().top + (window.scrollY || 0);
    for (var a = el.parentElement; a; a = a.parentElement) t += a.scrollTop || 0;
    return t;
  }
  function measure() {
    var stack = document.querySelector('.pmk-home-map-stack');
    var input = document.querySelector('.__CHANNEL__ input, input.__CHANNEL__');
    if (!shown(stack) || !input) return;
    // the live canvas, not the page's chair layer over it (pmk_nb/ui/live/page_script.py)
    var cs = stack.querySelectorAll('canvas:not(.pmk-live-page)'), canvas = cs[cs.length - 1];
    var width = Math.floor(stack.parentElement.clientWidth || stack.clientWidth);
    var height = Math.floor(window.innerHeight - docTop(stack) - __GAP__);
    // far down a notebook (JupyterLab) little is left below: the map then takes most of a window
    if (height < 0.4 * window.innerHeight) height = Math.floor(0.75 * window.innerHeight);
    var boxes = [];
    if (canvas) {
      var r = canvas.getBoundingClientRect(), k = r.width > 0 ? canvas.width / r.width : 1;
      OVER.forEach(function (sel) {
        stack.querySelectorAll(sel).forEach(function (el) {
          if (!shown(el)) return;
          var b = el.getBoundingClientRect();
          if (b.width > 0 && b.height > 0)
            boxes.push([Math.round((b.left - r.left) * k), Math.round((b.top - r.top) * k),
                        Math.round(b.width * k), Math.round(b.height * k)]);
        });
      });
    }
    var text = JSON.stringify({ w: width, h: height, boxes: boxes.slice(0, __MAX__) });
    if (text === window.__pmkFit.last) return;
    window.__pmkFit.last = text;
    input.value = text;
    input.dispatchEvent(new Event('input', { bubbles: true }));
    window.__pmkFit.sent += 1;
  }
  var pending = null;
  function soon() { if (pending === null) pending = setTimeout(function () { pending = null; measure(); }, 120); }
  window.addEventListener('resize', soon);
  window.addEventListener('orientationchange', soon);
  setInterval(measure, 700);  // panels shown or hidden, Home shown again: cheap, posts only changes
  soon();
})();
</script>"""


def page_html() -> str:
    return (
        SCRIPT.replace("__CHANNEL__", CHANNEL_CLASS)
        .replace("__OVER__", json.dumps(list(OVERLAY_SELECTORS)))
        .replace("__GAP__", str(BOTTOM_GAP_PX))
        .replace("__MAX__", str(MAX_BOXES))
    )


def _number(value: object) -> float | None:
    """A JSON number within the page-pixel bound (a string, bool or 400-digit integer is None)."""
    return page_number(value) if isinstance(value, int | float) else None


def parse_fit(text: object) -> tuple[int, int, list[tuple[float, float, float, float]]] | None:
    """(width, height, boxes) from the page's message, or None when it is not one (ignored)."""
    if not isinstance(text, str) or len(text) > 4000:
        return None
    try:
        raw = json.loads(text)
    except ValueError:
        return None
    if not isinstance(raw, dict):
        return None
    w, h = _number(raw.get("w")), _number(raw.get("h"))
    if w is None or h is None:
        return None
    width, height = (min(max(int(v), MIN_PX), MAX_PX) for v in (w, h))
    boxes: list[tuple[float, float, float, float]] = []
    items = raw.get("boxes")
    for box in items[:MAX_BOXES] if isinstance(items, list) else []:
        values = [_number(v) for v in box] if isinstance(box, list) and len(box) == 4 else []
        numbers = [v for v in values if v is not None]
        if len(numbers) == 4:
            boxes.append((numbers[0], numbers[1], numbers[2], numbers[3]))
    return width, height, boxes


class FitChannel:
    """The hidden widgets of the page's measurements and their effect on ``live``."""

    def __init__(self, live: LiveView) -> None:
        self.live = live
        self.channel = w.Text(value="", continuous_update=True, layout=w.Layout(display="none"))
        self.channel.add_class(CHANNEL_CLASS)
        self.channel.observe(self._on_message, names="value")
        self.chair_at = w.HTML("", layout=w.Layout(display="none"))
        self.chair_at.add_class(CHAIR_AT_CLASS)
        self.page = w.Output(layout=w.Layout(display="none"))
        from IPython.display import HTML

        self.page.append_display_data(HTML(page_html()))
        self.page.append_display_data(HTML(canvas_focus.SCRIPT))  # a press on the map never scrolls the page
        self.widget = w.Box([self.channel, self.chair_at, self.page], layout=w.Layout(display="none"))
        self.widget.add_class("pmk-home-fit")

    def _on_message(self, change: dict[str, Any]) -> None:
        fit = parse_fit(change.get("new"))
        if fit is None:
            return
        width, height, boxes = fit
        try:
            self.live.fit_page(width, height)
            size = self.live.canvas.width, self.live.canvas.height
            self.live.set_insets(insets_from_boxes(size[0], size[1], boxes))
        except (ValueError, TypeError) as err:  # a page's nonsense never reaches the screen as a traceback
            log.warning("page fit message ignored: %s", err)
            return
        self.tick()  # the view's new state is published with or without a preview running

    def tick(self) -> None:
        """Publish where the chair is drawn and the insets the view keeps it clear of (Home's info
        loop, a few times a second; only changes are sent): the page's tests work out the view."""
        at = self.live.chair_pixel()
        view = self.live.viewport
        if view is None:
            value = ""
        else:
            ins = view.insets
            chair = "" if at is None else f" data-x='{at[0]:.0f}' data-y='{at[1]:.0f}'"
            value = (
                f"<span data-canvas='{view.canvas_width} {view.canvas_height}' data-zoom='{view.zoom}'"
                f" data-insets='{ins.left:.1f} {ins.top:.1f} {ins.right:.1f} {ins.bottom:.1f}'{chair}></span>"
            )
        if self.chair_at.value != value:
            self.chair_at.value = value
