"""A press on the live map must not scroll the page: else the kernel gets the wrong point.

The behaviour worked around (ipycanvas 0.14.3, its page code ``CanvasView.onMouseDown``): on a
mouse press the canvas first calls ``this.el.focus()`` (for its key events), then reads the press's
canvas pixel as ``(event.clientY - rect.top) * height / rect.height`` with ``rect`` read AFTER the
focus.  Focusing an element that is partly scrolled out of view scrolls it into view, so ``rect``
has moved and ``clientY`` has not: the pixel sent is off by the scroll.  On Home the map takes the
window's height, so with the page scrolled to the map tools below it one press scrolled by 429 px
(13.9 m at zoom 1 in the demo): Measure said 10.33 m for 5 m, tap-to-go and Set pose took a point
that far off, and a drag jumped the map.  Touch is not affected (no focus on touch).

The fix: a ``<script>`` shown once in a hidden output (as :mod:`pmk_nb.ui.home.fit` does) makes
``focus()`` on the live canvas (``.pmk-live-canvas``, and only there) focus without scrolling, so
the pixel read is the one under the pointer.  Installed once per page, idempotent.
"""

from __future__ import annotations

LIVE_CANVAS_CLASS = "pmk-live-canvas"

SCRIPT = """<script>
(function () {
  var proto = HTMLCanvasElement.prototype;
  if (proto.__pmkFocusNoScroll) return;
  var focus = proto.focus;  // HTMLElement's, inherited
  proto.focus = function (options) {
    if (this.classList && this.classList.contains('__CLASS__'))
      options = Object.assign({}, options || {}, { preventScroll: true });
    return focus.call(this, options);
  };
  proto.__pmkFocusNoScroll = true;
})();
</script>""".replace("__CLASS__", LIVE_CANVAS_CLASS)
