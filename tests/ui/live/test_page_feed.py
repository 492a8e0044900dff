"""The page-drawn chair's feed (issue 41): the kernel sends poses and the view, not the chair's pixels."""

from __future__ import annotations

import json
from typing import Any

import pytest

from pmk_nb.clock import VirtualClock
from pmk_nb.ui.live import page_script
from pmk_nb.ui.live.render_loop import RenderLoop
from pmk_nb.ui.live.view import LiveView
from pmk_nb.viewport.glide import HEARTBEAT_S, late, pixel_affine
from tests.ui.live.test_live import Source, captured_commands, names, sample_grid


def feed_of(view: LiveView) -> dict[str, Any]:
    assert view.feed is not None
    return json.loads(view.feed.widget.value)  # type: ignore[no-any-return]


class TickedByTheTest(RenderLoop):
    """A loop that counts as running while the test calls ``render_frame`` itself, tick by tick."""

    @property
    def running(self) -> bool:
        return True


def running(view: LiveView) -> LiveView:
    view.loop.__class__ = TickedByTheTest
    return view


def page_view(clock: VirtualClock) -> tuple[LiveView, Source]:
    view = LiveView(320, 240, page_chair=True, clock=clock, fps=25)
    src = Source(clock)
    src.move(3.0, 2.0, 0.5, 0.4)
    src.set_scan(n=90)
    view.attach(src)
    return view, src


def test_the_kernel_frame_leaves_the_chair_to_the_page_and_sends_its_pose() -> None:
    clock = VirtualClock()
    view, src = page_view(clock)
    with captured_commands(view.canvas) as cmds:
        view.set_map(sample_grid())
    assert view.metrics.frames == 1
    assert "fillStyledCircles" not in names(cmds), "the page draws the chair, not the kernel"
    assert "fillPolygon" in names(cmds), "the laser is still the kernel's"
    msg = feed_of(view)
    assert view.viewport is not None and view.feed is not None
    assert msg["id"] == view.feed.id and f"pmk-live-{msg['id']}" in view.canvas._dom_classes
    assert msg["poses"] == [[src.odom.received, 3.0, 2.0, 0.5, 0.4]]  # type: ignore[union-attr]
    assert msg["px"] == pytest.approx(list(pixel_affine(view.viewport)), abs=1e-3)
    # the loop ticks at twice the canvas rate (25 fps) for the feed: a pose every 20 ms
    assert view.loop.fps == 50 and view.canvas_fps == 25
    assert msg["seq"] == 1 and msg["behind"] == pytest.approx(0.02)
    assert msg["next"] is None, "the loop is not running: no next update is promised, none can be late"
    running(view)
    clock.advance(0.04)
    src.move(3.1, 2.0, 0.5, 0.4)
    view.render_frame()
    assert feed_of(view)["next"] == pytest.approx(0.02)
    assert msg["r"] == pytest.approx(view.viewport.chair_radius_px(view.footprint_radius), abs=0.01)
    assert page_script.LINK_SLOW.startswith("Link slow")


def test_stopping_the_view_promises_no_more_updates() -> None:
    clock = VirtualClock()
    view, _src = page_view(clock)
    view.set_map(sample_grid())
    view.start()
    try:
        assert view.running
        clock.advance(0.1)
    finally:
        view.stop()
    msg = feed_of(view)
    assert msg["next"] is None
    assert not late(1e9, 0.0, msg["next"]), "a stopped view is not a slow link"


def test_the_kernels_own_look_still_draws_the_chair() -> None:
    view = LiveView(320, 240)
    src = Source()
    src.move(3.0, 2.0, 0.5, 0.4)
    view.attach(src)
    with captured_commands(view.canvas) as cmds:
        view.set_map(sample_grid())
    assert names(cmds).count("fillStyledCircles") == 1
    assert view.feed is None and view.page_widget is None


def test_moving_poses_go_each_frame_a_parked_chair_on_the_heartbeat() -> None:
    clock = VirtualClock()
    view, src = page_view(clock)
    view.set_map(sample_grid())
    running(view)
    assert view.feed is not None
    for i in range(1, 4):  # driving: a new pose each frame, the last few kept, oldest first
        clock.advance(0.04)
        src.move(3.0 + 0.1 * i, 2.0, 0.5, 0.4)
        view.render_frame()
    msg = feed_of(view)
    assert [p[1] for p in msg["poses"]] == pytest.approx([3.0, 3.1, 3.2, 3.3])
    assert msg["next"] == pytest.approx(0.02)
    sent = view.feed.sent
    clock.advance(0.04)  # stopped: the frame is skipped, but the promise of a message is kept
    assert view.render_frame() is False
    assert view.feed.sent == sent + 1 and feed_of(view)["next"] == HEARTBEAT_S
    for _ in range(int(HEARTBEAT_S / 0.04) - 1):  # parked: nothing until the heartbeat is due
        clock.advance(0.04)
        view.render_frame()
    assert view.feed.sent == sent + 1
    clock.advance(0.08)
    view.render_frame()
    assert view.feed.sent == sent + 2, "a parked chair's pose goes again on the heartbeat"


def test_between_canvas_frames_the_ticks_send_only_poses() -> None:
    clock = VirtualClock()
    view, src = page_view(clock)
    view.set_map(sample_grid())
    running(view)
    view.set_zoom(6)  # following the chair: the view moves with every pose
    view.render_frame()  # the zoom's frame, at the loop's next tick
    frames = view.metrics.frames
    got, placed = [], []
    for i in range(1, 9):  # 50 Hz ticks, the chair moving every tick
        clock.advance(0.02)
        src.move(3.0 + 0.05 * i, 2.0, 0.5, 0.4)
        with captured_commands(view.canvas) as cmds:
            drawn = view.render_frame()
        got.append((drawn, bool(cmds)))
        msg = feed_of(view)
        assert msg["poses"][-1][1] == pytest.approx(3.0 + 0.05 * i), "every tick's pose goes to the page"
        placed.append(msg["px"])
    assert got == [(False, False), (True, True)] * 4, "a canvas frame every other tick, nothing sent between"
    # the page places the chair by the view of the frame on the canvas, not by the view that followed on
    assert all(placed[i] == placed[i - 1] for i in range(2, 8, 2)), placed
    assert len({json.dumps(p) for p in placed}) > 1, "the view should follow the chair"
    assert view.metrics.frames == frames + 4
    view.zoom_in()  # a zoom draws at the next tick, between canvas frames too
    clock.advance(0.001)
    assert view.render_frame() and view.metrics.frames == frames + 5


def test_a_capped_page_keeps_its_ticks() -> None:
    view = LiveView(320, 240, page_chair=True, fps=11)  # the classroom's cap: two cores for ten pages
    assert view.loop.fps == view.canvas_fps == 11


def test_a_new_source_forgets_the_old_chairs_poses() -> None:
    clock = VirtualClock()
    view, _src = page_view(clock)
    view.set_map(sample_grid())
    other = Source(clock)
    clock.advance(0.04)
    other.move(-1.0, 0.0)
    view.attach(other)
    assert [p[1] for p in feed_of(view)["poses"]] == [-1.0]
