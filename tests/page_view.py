"""The live view as the page shows it, for browser tests that press on the map (issue 28).

Home's canvas takes the page's room and the view keeps the followed chair clear of the panels
over it (insets); the kernel publishes the canvas size, zoom level and insets on
``.pmk-home-chair-at span`` (:mod:`pmk_nb.ui.home.fit`), and this builds the same
:class:`pmk_nb.viewport.Viewport`.  At zoom level 1 the map fits the uncovered part, so the view
does not move while the chair does.
"""

from __future__ import annotations

import time
from typing import Any

from pmk_nb.viewport import Insets, Viewport

STATE_JS = """() => {
  const s = document.querySelector('.pmk-home-chair-at span');
  const cs = document.querySelectorAll('.pmk-home-map-stack canvas:not(.pmk-live-page)'), c = cs[cs.length - 1];
  if (!s || !c || !s.dataset.insets) return null;
  const r = c.getBoundingClientRect();
  return { canvas: s.dataset.canvas, zoom: s.dataset.zoom, insets: s.dataset.insets,
           px: [c.width, c.height], css: [r.width, r.height] };
}"""


def settled_state(page: Any, timeout: float = 60.0) -> dict[str, Any]:
    """The view's state once the canvas has the page's size (drawn 1:1) and is steady: ``px``
    (canvas pixels), ``zoom`` and ``insets`` (left, top, right, bottom)."""
    deadline = time.monotonic() + timeout
    last: Any = None
    while time.monotonic() < deadline:
        state = page.evaluate(STATE_JS)
        fitted = state is not None and state["canvas"] == f"{state['px'][0]} {state['px'][1]}"
        if fitted and state == last and abs(state["px"][0] - state["css"][0]) < 2:
            insets = tuple(float(v) for v in state["insets"].split())
            return {"px": tuple(state["px"]), "zoom": int(state["zoom"]), "insets": insets}
        last = state
        time.sleep(0.5)
    raise AssertionError(f"the live canvas did not settle to the page's size: {last}")


def page_view(page: Any, grid: Any, timeout: float = 60.0) -> Viewport:
    """The page's view of ``grid`` (see :func:`settled_state`)."""
    state = settled_state(page, timeout)
    view = Viewport.for_grid(grid, *state["px"])
    view.set_zoom(state["zoom"])
    view.set_insets(Insets(*state["insets"]))
    return view
