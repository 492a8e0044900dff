"""Late-joining pages still get the live frames: every ipycanvas message names its layer.

A fake page stands in for ipycanvas's ``CanvasManagerModel`` in the browser: it decodes the
messages the kernel's canvas manager sends and, like the real one, draws each command on the
canvas the last ``switchCanvas`` it received named, or nowhere when it has received none (a page
that connected after that switch was sent: Voilà drops earlier messages, a reload starts fresh).
It also keeps ipycanvas's list of canvases a message refreshes (``onCommand``: the canvas current
when the message starts, then one entry per ``switchCanvas``), each refresh a composite on screen.
"""

from __future__ import annotations

import contextlib
import json
import math
import time
from collections.abc import Iterator
from typing import Any

import numpy as np
from ipycanvas import Canvas
from ipycanvas.canvas import _CMD_LIST, _CanvasManager

from pmk_nb.chair import Odometry
from pmk_nb.grid import OccupancyGrid
from pmk_nb.ui.live.canvas_fix import make_messages_name_their_layer
from pmk_nb.ui.live.view import LiveView


class FakePage:
    """The page side: ``drawn`` holds (canvas model id, command), ``lost`` the commands with no canvas."""

    def __init__(self) -> None:
        self.current: str | None = None
        self.drawn: list[tuple[str, str]] = []
        self.lost: list[str] = []
        self.refreshed: list[list[str]] = []  # per message, the canvases refreshed, in order

    def receive(self, buffers: list[Any]) -> None:
        raw = json.loads(bytes(memoryview(buffers[0])).decode())
        batch = raw if raw and isinstance(raw[0], list) else [raw]
        refresh = [self.current] if self.current is not None else []
        for cmd in batch:
            name = _CMD_LIST[cmd[0]]
            if name == "switchCanvas":
                self.current = str(cmd[1][0]).removeprefix("IPY_MODEL_")
                refresh.append(self.current)
            elif self.current is None:
                self.lost.append(name)
            else:
                self.drawn.append((self.current, name))
        self.refreshed.append(refresh)


@contextlib.contextmanager
def page_joins(manager: Any) -> Iterator[FakePage]:
    """A page that connects now: it sees only the messages sent from here on."""
    page = FakePage()
    own = manager.__dict__.get("send")
    forward = manager.send

    def send(content: Any, buffers: list[Any] | None = None) -> None:
        page.receive(buffers or [])
        forward(content, buffers)

    manager.send = send
    try:
        yield page
    finally:
        if own is not None:
            manager.send = own
        else:
            del manager.send


class Moving:
    """A chair that is somewhere else at every call."""

    def latest_odom(self) -> Odometry:
        t = time.monotonic()
        return Odometry(3.0 + math.sin(t), 2.0, 0.0, 0.3, 0.0, None, t)

    def latest_pose(self) -> None:
        return None

    def latest_scan(self) -> None:
        return None


def test_ipycanvas_switches_layer_only_on_change_so_a_late_page_loses_commands() -> None:
    # the behaviour worked around, on a manager of its own without the fix: if ipycanvas ever
    # names the layer in every message itself, this fails and the fix can go
    manager = _CanvasManager()
    layer = Canvas(width=10, height=10, _canvas_manager=manager)
    layer.clear()  # seen by nobody: the page is not there yet
    with page_joins(manager) as page:
        layer.fill_rect(0, 0, 5, 5)
    assert page.lost == ["fillRect"] and page.drawn == []


def test_fixed_manager_names_the_layer_in_every_message() -> None:
    manager = _CanvasManager()
    layer = Canvas(width=10, height=10, _canvas_manager=manager)
    assert make_messages_name_their_layer(layer)
    send_custom = manager._send_custom
    assert make_messages_name_their_layer(layer) and manager._send_custom is send_custom  # once only
    layer.clear()
    with page_joins(manager) as page:
        layer.fill_rect(0, 0, 5, 5)
        layer.stroke_rect(0, 0, 5, 5)
    assert page.lost == []
    assert page.drawn == [(layer.model_id, "fillRect"), (layer.model_id, "strokeRect")]


def test_a_page_joining_after_the_first_frames_gets_the_next_dynamic_only_frame() -> None:
    view = LiveView(200, 150)
    view.set_map(OccupancyGrid(np.zeros((100, 150), np.int8), 0.1))
    view.attach(Moving())
    for _ in range(3):  # map + chair, then chair only: all before the page connects
        assert view.render_frame()
    assert view.metrics.map_draws == 1
    with page_joins(view.canvas._canvas_manager) as page:
        assert view.render_frame()  # no client_ready yet: a frame of the dynamic layer only
    assert page.lost == []
    assert (view.dyn_layer.model_id, "fillStyledCircles") in page.drawn
    assert all(model == view.dyn_layer.model_id for model, _ in page.drawn)
    view.close()


def test_each_live_frame_refreshes_the_dynamic_layer_once() -> None:
    # ipycanvas's page refreshed the layer a frame switched to twice when the previous frame had
    # left it current: every frame composited twice on screen (a classroom page: 24 composites a
    # second for 12 frames); each batch now ends on a parking canvas that nothing shows
    view = LiveView(200, 150)
    view.set_map(OccupancyGrid(np.zeros((100, 150), np.int8), 0.1))
    view.attach(Moving())
    assert view.render_frame()
    with page_joins(view.canvas._canvas_manager) as page:
        for _ in range(3):
            assert view.render_frame()
    dyn, layers = view.dyn_layer.model_id, {view.dyn_layer.model_id, view.map_layer.model_id}
    assert len(page.refreshed) == 3
    for refresh in page.refreshed:
        assert refresh.count(dyn) == 1, refresh
    assert all(refresh[0] not in layers for refresh in page.refreshed[1:])  # each starts on the parking canvas
    assert page.current not in layers
    view.close()
