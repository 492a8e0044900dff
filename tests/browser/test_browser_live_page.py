"""The page draws the chair between the kernel's frames (issue 41), in Chromium against Voilà.

The demo chair patrols; Home's preview starts by itself.  Over a window of feed updates the page
layer (``window.__pmkLive``, :mod:`pmk_nb.ui.live.page_script`) must have drawn more pictures than
the kernel drew frames, and the chair's marker must have moved while the kernel's frame stayed the
same (the same ``seq``).  Then the kernel is paused (SIGSTOP) and the page must say "Link slow"
rather than freeze silently, and stop saying it once the kernel runs again.  Relations and generous
deadlines only: no frame rate is asserted.
"""

from __future__ import annotations

import contextlib
import math
import os
import signal
from collections.abc import Iterator
from typing import Any

import psutil
import pytest

from pmk_nb.ui.live.page_script import LINK_SLOW
from tests.browser.kiosk_page import ARTIFACTS, VIEWPORT, chromium_page

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]

STATS_JS = """() => {
  const S = window.__pmkLive, ids = Object.keys(S.views);
  const V = ids.length ? S.views[ids[0]] : null;
  return { frames: S.frames, updates: S.updates, seq: V && V.msg ? V.msg.seq : 0, trace: S.trace.slice(),
           error: S.error || null };
}"""

#: the overlay and the live canvas: same box, same pixel size; the overlay's chair pixels
OVERLAY_JS = """() => {
  const o = document.querySelector('canvas.pmk-live-page'), c = document.querySelector('canvas.pmk-live-canvas');
  if (!o || !c) return null;
  const a = o.getBoundingClientRect(), b = c.getBoundingClientRect();
  const d = o.getContext('2d').getImageData(0, 0, o.width, o.height).data;
  let blue = 0;
  for (let i = 0; i < d.length; i += 4) if (d[i + 3] > 200 && d[i + 2] > 200 && d[i] < 60) blue += 1;
  return { overlay: [a.left, a.top, a.width, a.height, o.width, o.height],
           canvas: [b.left, b.top, b.width, b.height, c.width, c.height], blue: blue,
           events: getComputedStyle(o).pointerEvents };
}"""


def kernels_of_this_test() -> list[psutil.Process]:
    """The ipykernel processes started under this test (Voilà is its child): never anyone else's."""
    me = psutil.Process(os.getpid())
    return [p for p in me.children(recursive=True) if "ipykernel" in " ".join(p.cmdline())]


@contextlib.contextmanager
def paused(procs: list[psutil.Process]) -> Iterator[None]:
    for p in procs:
        p.send_signal(signal.SIGSTOP)
    try:
        yield
    finally:
        for p in procs:
            with contextlib.suppress(psutil.NoSuchProcess):
                p.send_signal(signal.SIGCONT)


def moved_within_one_kernel_frame(trace: list[list[float]]) -> float:
    """The largest distance (canvas px) the page moved the chair while the kernel's frame stayed the same."""
    best = 0.0
    by_seq: dict[int, list[tuple[float, float]]] = {}
    for seq, x, y, *_ in trace:
        by_seq.setdefault(int(seq), []).append((x, y))
    for points in by_seq.values():
        best = max(best, max(math.dist(points[0], p) for p in points))
    return best


def test_the_page_draws_the_chair_between_kernel_frames_and_says_link_slow(kiosk: tuple[str, Any]) -> None:
    from playwright.sync_api import expect

    url, _world = kiosk
    with chromium_page(url, viewport=VIEWPORT) as page:
        expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
        page.wait_for_function("() => window.__pmkLive && window.__pmkLive.frames > 2", timeout=60_000)
        geometry = page.evaluate(OVERLAY_JS)
        assert geometry is not None, "no overlay canvas over the live canvas"
        assert geometry["overlay"] == pytest.approx(geometry["canvas"], abs=1.0), geometry
        assert geometry["events"] == "none", "the overlay must let gestures through to the map"

        # -- a window of kernel updates while the chair patrols
        first = page.evaluate(STATS_JS)
        page.wait_for_function(
            "(n) => window.__pmkLive.updates >= n + 40", arg=first["updates"], timeout=120_000, polling=200
        )
        second = page.evaluate(STATS_JS)
        assert second["error"] is None, second["error"]
        kernel_frames = second["seq"] - first["seq"]
        page_frames = second["frames"] - first["frames"]
        assert kernel_frames > 0, "the kernel drew no frame in the window: is the chair moving?"
        assert page_frames > kernel_frames, f"page drew {page_frames} pictures for {kernel_frames} kernel frames"
        moved = moved_within_one_kernel_frame(second["trace"])
        assert moved > 0.3, f"the chair did not move between kernel frames (at most {moved:.2f} px)"
        assert page.evaluate(OVERLAY_JS)["blue"] > 20, "the chair is not drawn on the overlay"

        # -- the kernel stops answering: the page says so instead of freezing silently
        status = page.locator(".pmk-live-link[role=status]")
        kernels = kernels_of_this_test()
        assert kernels, "found no kernel process under this test"
        with paused(kernels):
            expect(status).to_contain_text("Link slow", timeout=30_000)
            assert LINK_SLOW.startswith("Link slow")
            ARTIFACTS.mkdir(exist_ok=True)
            page.screenshot(path=str(ARTIFACTS / "live-link-slow.png"))
            before = page.evaluate(STATS_JS)["trace"][-1:]
            page.wait_for_timeout(500)
            after = page.evaluate(STATS_JS)["trace"][-1:]
            # held: at most one update past the newest pose, so the picture stops changing
            assert before == after, "the chair kept moving with no updates: extrapolated beyond one update"
        expect(status).to_have_text("", timeout=60_000)
