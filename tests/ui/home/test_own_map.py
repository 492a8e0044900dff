"""Home shows the chair's own /map: the watched message -> grid -> screen image, the name given to it,
and Home against the simulated chair when nothing was sent from this dashboard (issue 29)."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from pmk_nb.chair.link.streams.mapwatch import MapWatch
from pmk_nb.grid import GRAY_UNKNOWN, OccupancyGrid
from pmk_nb.ui.common.widgets import escape
from pmk_nb.ui.home.info import PRESS_PREVIEW_TEXT
from pmk_nb.ui.home.own_map import CHAIRS_MAP, same_map
from pmk_nb.viewport import clean_occupancy, window_image

CHAIRS = escape(CHAIRS_MAP)  # as the page shows it


def wait_for(cond: Callable[[], bool], timeout: float = 10.0) -> bool:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if cond():
            return True
        time.sleep(0.05)
    return cond()


def map_msg(data: list[int], width: int, height: int, resolution: float = 0.5) -> dict[str, Any]:
    origin = {"position": {"x": -1.0, "y": 2.0, "z": 0.0}, "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}}
    info = {"width": width, "height": height, "resolution": resolution, "origin": origin}
    return {"header": {"frame_id": "map"}, "info": info, "data": data}


def test_a_watched_map_becomes_an_image_with_row_0_at_the_bottom_and_unknown_grey() -> None:
    watch = MapWatch("/map", threading.Lock())
    assert watch.latest() == (0, None)
    # 3 x 2 cells; ROS order: row 0 (bottom) first. Bottom-left occupied, top-right unknown.
    watch._on_map(map_msg([100, 0, 0, 0, 0, -1], 3, 2))  # what the I/O thread does: store only
    count, grid = watch.latest()
    assert count == 1 and grid is not None
    assert (grid.width, grid.height, grid.resolution, grid.origin[:2]) == (3, 2, 0.5, (-1.0, 2.0))
    assert grid.value_at(-0.75, 2.25) == 100 and grid.value_at(0.25, 2.75) == -1
    assert watch.latest()[1] is grid  # converted once per map
    image = window_image(clean_occupancy(grid.data)[::-1], 10.0, 0, 0, 30, 20)  # as the map layer draws it
    assert image.shape == (20, 30)
    assert image[15, 5] == 0  # bottom-left: black wall
    assert image[5, 25] == GRAY_UNKNOWN  # top-right: unknown grey
    assert image[5, 5] == 254  # free: white
    watch._on_map({"info": {"width": 2}})  # malformed: no grid, a reason
    count, grid = watch.latest()
    assert count == 2 and grid is None and watch.error is not None and "malformed" in watch.error


def test_same_map_tolerates_a_few_cells_but_not_another_frame() -> None:
    data = np.zeros((50, 40), np.int8)
    data[10, :] = 100
    ours = OccupancyGrid(data, 0.05, (1.0, 2.0, 0.0))
    theirs = OccupancyGrid(data.copy(), 0.05, (1.0, 2.0, 0.0))
    theirs.data[0, :5] = -1  # a chair's image reader rounds a few cells differently
    assert same_map(ours, theirs)
    assert not same_map(ours, OccupancyGrid(data.copy(), 0.05, (3.0, 2.0, 0.0)))
    assert not same_map(ours, OccupancyGrid(data.copy(), 0.1, (1.0, 2.0, 0.0)))
    assert not same_map(ours, OccupancyGrid(np.full((50, 40), 100, np.int8), 0.05, (1.0, 2.0, 0.0)))
    assert not same_map(None, theirs)


@pytest.fixture
def chair_only(tmp_path: Path, sim_factory: Callable[..., Any]) -> Iterator[tuple[Any, Any]]:
    """A session with a chair profile but no map sent from this dashboard; the chair has its own map."""
    from pmk_nb.chair import ChairProfile, ProfileStore
    from pmk_nb.library import MapsFolder
    from pmk_nb.sim import demo_grid
    from pmk_nb.ui.common.context import AppContext

    sim = sim_factory(grid=demo_grid(), start_pose=(2.0, 6.0, 0.0), odom_rate=20.0, scan_rate=5.0, rays=90)
    profiles = ProfileStore(tmp_path / "profiles.json", secrets=False)
    profiles.save(ChairProfile(name="sim", host="127.0.0.1", port=sim.port))
    ctx = AppContext(MapsFolder(tmp_path / "maps"), profiles, config_dir=tmp_path / "cfg")
    try:
        yield ctx, sim
    finally:
        ctx.close()


@pytest.mark.slow
def test_home_shows_the_chairs_own_map_when_nothing_was_sent(chair_only: Any, tmp_path: Path) -> None:
    from pmk_nb.rosmap import read_map, write_map
    from pmk_nb.ui.home.screen import HomeScreen

    ctx, sim = chair_only
    home = HomeScreen(ctx, canvas_width=320, canvas_height=240, fps=10)
    try:
        assert ctx.current_map is None
        assert "No current map" not in home.ui.warning.value
        assert CHAIRS in home.ui.map_label.value and home.preview_button.layout.display != "none"
        assert PRESS_PREVIEW_TEXT in home.ui.map_note.value  # issue 40: a blank page said nothing before Preview
        assert home.start_preview() and home.running
        assert PRESS_PREVIEW_TEXT not in home.ui.map_note.value
        chair_grid = sim.grid
        assert wait_for(lambda: home.live.grid is not None, 15.0), home.ui.warning.value
        shown = home.live.grid
        assert shown is not None and np.array_equal(shown.data, chair_grid.data)
        assert shown.resolution == pytest.approx(chair_grid.resolution)
        assert wait_for(lambda: home.live.metrics.map_draws >= 1, 5.0)
        assert CHAIRS in home.ui.map_label.value and "Maps" in home.ui.map_label.value

        # the chair loads another map (SLAM, pmk send, another tablet): Home follows it
        other = OccupancyGrid(np.zeros((60, 80), np.int8), 0.1, (0.0, 0.0, 0.0))
        other.data[30, :] = 100
        files = write_map(other, sim.maps_dir, "lab")
        assert sim.load_map(files.yaml) == 0
        assert wait_for(lambda: home.live.grid is not None and home.live.grid.width == 80, 15.0)
        assert np.array_equal(home.live.grid.data, read_map(files.yaml).data)

        # the maps folder's record says that map was sent from here: its name is shown
        ctx.set_current_map("lab", files.yaml, None)
        assert wait_for(lambda: "lab" in home.ui.map_label.value, 5.0), home.ui.map_label.value
        assert CHAIRS not in home.ui.map_label.value
    finally:
        home.close()


def test_the_map_watch_survives_a_one_shot_map_read(sim_factory: Callable[..., Any]) -> None:
    """roslibpy's unsubscribe drops every listener of /map: the watch listens again after fetch_map."""
    from pmk_nb.chair.link import ChairLink
    from pmk_nb.rosmap import write_map

    sim = sim_factory(grid=OccupancyGrid(np.zeros((40, 50), np.int8), 0.1, (0.0, 0.0, 0.0)))
    link = ChairLink("127.0.0.1", sim.port)
    try:
        link.connect(timeout=10.0)
        link.watch_map(True)
        assert link.watching_map
        assert wait_for(lambda: link.latest_map()[0] >= 1, 10.0)
        assert link.fetch_map(timeout=10.0).width == 50  # a one-shot read of the same topic
        seen = link.latest_map()[0]
        files = write_map(OccupancyGrid(np.zeros((30, 70), np.int8), 0.1, (0.0, 0.0, 0.0)), sim.maps_dir, "wide")
        assert sim.load_map(files.yaml) == 0
        assert wait_for(lambda: link.latest_map()[0] > seen, 10.0)
        grid = link.latest_map()[1]
        assert grid is not None and grid.width == 70
        link.watch_map(False)
        assert not link.watching_map and link.latest_map() == (0, None)
    finally:
        link.close()


def test_attach_from_two_threads_never_joins_a_thread_not_yet_started(monkeypatch: pytest.MonkeyPatch) -> None:
    """Home's connect thread stops the preview (``attach(None)``) while the page's thread attaches a link:
    the watcher thread must be started before another attach can see it (a full run raised
    "cannot join thread before it is started" there, and Home never said the chair was unreachable)."""
    from pmk_nb.ui.home import own_map as module

    own = module.OwnMap()
    errors: list[BaseException] = []
    real_thread = threading.Thread

    class Interleaved(real_thread):
        def start(self) -> None:
            if self.name == "pmk-own-map":  # the other thread's attach(None) runs right here

                def stop() -> None:
                    try:
                        own.attach(None)
                    except BaseException as err:  # collected for the assertion
                        errors.append(err)

                other = real_thread(target=stop)
                other.start()
                other.join(5)
            super().start()

    monkeypatch.setattr(module.threading, "Thread", Interleaved)

    class Link:
        is_connected, watching_map = False, False

    own.attach(Link())
    own.attach(None)
    assert errors == []
