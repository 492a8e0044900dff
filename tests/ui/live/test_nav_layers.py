"""The navigation layers on the live view (issue 40): a costmap's RGBA image is sent once per change and
placed by a canvas transform; the toggles follow the simulated chair's costmaps, footprint, local plan
and markers through the real link."""

from __future__ import annotations

import re
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from ipycanvas import Canvas

from pmk_nb.chair.link.streams.navlayers import FOOTPRINT, GLOBAL, LOCAL, LOCAL_PLAN, MARKERS, Costmap
from pmk_nb.ui.live.nav_layers import CostmapOverlay, NavLayers
from pmk_nb.ui.live.view import LiveView
from pmk_nb.viewport import Transform2D
from tests.fixtures_sim import room_grid
from tests.ui.live.test_live import Source, captured_commands, names, sample_grid


@pytest.fixture
def put_shapes(monkeypatch: pytest.MonkeyPatch) -> list[tuple[int, ...]]:
    """The shape of every image put on any canvas."""
    shapes: list[tuple[int, ...]] = []
    original = Canvas.put_image_data

    def put(self: Canvas, image_data: np.ndarray, x: int = 0, y: int = 0) -> None:
        shapes.append(tuple(np.asarray(image_data).shape))
        original(self, image_data, x, y)

    monkeypatch.setattr(Canvas, "put_image_data", put)
    return shapes


def test_a_costmap_is_put_once_as_rgba_and_moved_by_a_transform(put_shapes: list[tuple[int, ...]]) -> None:
    view = LiveView(300, 200)
    view.set_map(sample_grid())
    overlay = CostmapOverlay()
    view.map_overlays.append(overlay)
    data = np.zeros((20, 30), np.int8)
    data[0, :] = 100
    overlay.set(Costmap(data, 0.05, (0.0, 0.0, 0.0), "map", "/global_costmap/costmap", 1), Transform2D())
    put_shapes.clear()
    with captured_commands(view.canvas) as cmds:
        view.request_redraw()
    assert put_shapes == [(20, 30, 4)]  # RGBA, one pixel per cell
    assert {"save", "translate", "drawImage", "restore"} <= set(names(cmds))
    put_shapes.clear()
    view.pan(15, 0)  # the map layer is repainted: the costmap is drawn again, not sent again
    view.request_redraw()
    assert put_shapes == [] and overlay.puts == 1
    overlay.set(Costmap(data, 0.05, (0.0, 0.0, 0.0), "map", "/global_costmap/costmap", 2), Transform2D())
    view.request_redraw()
    assert put_shapes == [(20, 30, 4)] and overlay.puts == 2  # a new costmap: sent once
    before = overlay.version
    overlay.set(overlay.costmap, Transform2D(0.001, 0.0, 0.0))  # its frame moved by a millimetre: no redraw
    assert overlay.version == before
    turned = Transform2D(1.0, 0.0, 0.5)
    overlay.set(overlay.costmap, turned)
    with captured_commands(view.canvas) as cmds:
        view.request_redraw()
    assert "rotate" in names(cmds) and put_shapes == [(20, 30, 4)]
    view.close()


def test_footprint_local_plan_and_every_marker_kind_become_canvas_calls() -> None:
    from pmk_nb.chair.link import Footprint, PlannedPath
    from pmk_nb.ui.live.nav_layers import VectorOverlay
    from pmk_nb.viewport import PlanarMarker

    view = LiveView(300, 200)
    view.set_map(sample_grid())
    overlay = VectorOverlay()
    view.overlays.append(overlay)
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    markers = [
        PlanarMarker(kind, (2.0, 2.0, 0.0), (0.1, 0.1, 0.3), (1, 0, 0, 1), square, "label")
        for kind in (0, 1, 2, 4, 5, 8, 9)  # ARROW, CUBE, SPHERE, LINE_STRIP, LINE_LIST, POINTS, TEXT
    ]
    overlay.set(
        ("k",),
        footprint=(Footprint(square, "odom", "/fp"), Transform2D()),
        plan=(PlannedPath(square, "odom", "/local_plan", 0.0), Transform2D(1.0, 0.0, 0.0)),
        markers=[(m, Transform2D()) for m in markers],
    )
    with captured_commands(view.canvas) as cmds:
        view.request_redraw()
    got = names(cmds)
    assert got.count("strokePolygon") == 1  # the footprint
    assert got.count("fillPolygon") >= 3  # arrow, cube, sphere (and the laser's free space, if any)
    assert {"strokeLines", "strokeLineSegments", "fillRects", "fillText"} <= set(got)
    before = overlay.version
    overlay.set(("k",), footprint=None, plan=None, markers=[])  # the same key: nothing new to draw
    assert overlay.version == before and overlay.footprint is not None
    view.close()


@pytest.mark.slow
def test_the_toggles_follow_the_simulated_chairs_layers(
    sim_factory: Callable[..., Any], link_factory: Callable[[Any], Any]
) -> None:
    grid = room_grid(8.0, 5.0, resolution=0.05)
    sim = sim_factory(grid=grid, ros="ros2", start_pose=(1.5, 2.5, 0.0))
    link = link_factory(sim)
    link.start_streams()
    view = LiveView(320, 200)
    view.set_map(grid)
    layers = NavLayers(view)
    layers.attach(link)
    view.attach(link)
    layers.tick()
    assert layers.state.value == "" and not layers.watch.subscribed  # all off: nothing looked up or subscribed
    for layer in (GLOBAL, LOCAL, FOOTPRINT, LOCAL_PLAN, MARKERS):
        layers.toggles[layer].value = True
    # rosbridge_suite holds a socket's service calls while an action goal runs on it (the simulator's
    # official mode does too): the lookup is answered before the goal is sent
    deadline = time.monotonic() + 15.0
    while time.monotonic() < deadline and len(layers.watch.subscribed) < 5:
        layers.tick()
        time.sleep(0.05)
    assert set(layers.watch.subscribed) == {GLOBAL, LOCAL, FOOTPRINT, LOCAL_PLAN, MARKERS}
    handle = link.navigate_to(6.5, 2.5, 0.0)  # a local plan and the goal's markers while it runs

    seen: dict[str, str] = {}
    keys = ("global-costmap", "local-costmap", "footprint", "local-plan", "markers")
    deadline = time.monotonic() + 30.0
    while time.monotonic() < deadline and len(seen) < len(keys):
        layers.tick()
        for key in keys:
            found = re.search(f'data-{key}="([^"]+)"', layers.state.value)
            if found:
                seen.setdefault(key, found.group(1))
        time.sleep(0.05)
    assert seen.get("global-costmap") == "160x100 cells, /global_costmap/costmap", seen
    assert seen.get("local-costmap", "").startswith("80x80 cells") and seen.get("markers") == "5 markers", seen
    assert re.fullmatch(r"\d+ points, /local_costmap/published_footprint", seen.get("footprint", "")), seen
    assert re.fullmatch(r"\d+ poses, /local_plan", seen.get("local-plan", "")), seen
    with captured_commands(view.canvas) as cmds:
        view.request_redraw()
    got = names(cmds)
    assert got.count("drawImage") >= 3  # the map tile and both costmaps
    assert "strokePolygon" in got  # the footprint
    handle.cancel()
    layers.toggles[GLOBAL].value = False
    layers.tick()
    assert GLOBAL not in layers.watch.subscribed and "data-global-costmap" not in layers.state.value
    layers.close()
    view.close()
    assert Source  # the shared helpers come from the live view's tests
