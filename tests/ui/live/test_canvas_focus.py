"""A press on the live map reads the pixel under the pointer although the page was scrolled (issue 29).

ipycanvas focuses the canvas on a mouse press, then reads the press's pixel from the canvas's
rectangle AFTER the focus (:mod:`pmk_nb.ui.live.canvas_focus`).  These tests replay exactly that read in
Chromium on a bare page (no Voilà: a few seconds): a canvas partly scrolled out of its scrolling
box, pressed on its visible part.
"""

from __future__ import annotations

from typing import Any

import pytest

from pmk_nb.ui.live import canvas_focus
from tests.browser.kiosk_page import chromium_page

PAGE = """<style>body { margin: 0 }</style><div id="box" style="height: 400px; overflow: auto">
  <div style="height: 300px"></div>
  <canvas class="pmk-live-canvas" tabindex="0" width="300" height="380" style="display: block"></canvas>
  <canvas class="other" tabindex="0" width="300" height="380" style="display: block"></canvas>
  <div style="height: 800px"></div>
</div>"""

# ipycanvas 0.14.3's CanvasView.onMouseDown + getCoordinates, on a press 100 px below the window's
# top: the canvas pixel row the kernel is told, and the row that was under the pointer
PRESS_JS = """(sel) => {
  const box = document.getElementById('box'), c = document.querySelector(sel);
  box.scrollTop = 0;
  box.scrollTop = c.offsetTop - box.offsetTop + 200;  // the canvas's top 200 px are scrolled away
  const clientY = 100, before = c.getBoundingClientRect();
  c.focus();
  const t = c.getBoundingClientRect();
  return { sent: c.height * (clientY - t.top) / t.height, under: clientY - before.top };
}"""


def _press(page: Any, selector: str) -> dict[str, float]:
    return page.evaluate(PRESS_JS, selector)


def _install(page: Any) -> None:
    """The script as the page runs it (Voilà runs the hidden output's ``<script>``)."""
    page.add_script_tag(content=canvas_focus.SCRIPT.removeprefix("<script>").removesuffix("</script>"))


@pytest.mark.browser
@pytest.mark.timeout(120)
def test_a_press_on_the_live_canvas_reads_the_pixel_under_the_pointer() -> None:
    with chromium_page("about:blank", viewport={"width": 800, "height": 600}) as page:
        page.set_content(PAGE)
        plain = _press(page, "canvas.other")
        # the trigger, as the browser does it: focus scrolled the canvas into view, the row is off
        assert abs(plain["sent"] - plain["under"]) > 100, plain
        _install(page)
        live = _press(page, "canvas.pmk-live-canvas")
        assert live["under"] == pytest.approx(300.0)  # 200 px scrolled away + 100 px into the window
        assert live["sent"] == pytest.approx(live["under"], abs=0.5), live
        # only the live canvas changes: any other element's focus scrolls as before
        assert abs(_press(page, "canvas.other")["sent"] - plain["under"]) > 100
        _install(page)
        assert _press(page, "canvas.pmk-live-canvas")["sent"] == pytest.approx(300.0, abs=0.5)  # twice: same


def test_home_installs_the_script_once_beside_the_fit_channel() -> None:
    from pmk_nb.ui.home.fit import FitChannel
    from pmk_nb.ui.live.view import LiveView

    fit = FitChannel(LiveView(320, 240))
    shown = [out["data"]["text/html"] for out in fit.page.outputs]
    assert shown.count(canvas_focus.SCRIPT) == 1
    assert "preventScroll: true" in canvas_focus.SCRIPT
