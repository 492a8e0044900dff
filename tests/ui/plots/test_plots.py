"""Home's Plots panel, topic inspector and planned path against the simulated chair (real link, real
widgets; issue 29 item 4): samples from the info timer, the chart drawn at a low rate only while
open, one throttled subscription for the inspected topic (gone when closed), the plan drawn."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.chair import ChairProfile, ProfileStore
from pmk_nb.library import MapsFolder
from pmk_nb.ui.common.context import AppContext
from pmk_nb.ui.plots.panel import PlotsPanel
from tests.fixtures_sim import room_grid, write_test_map
from tests.helpers import wait_ticking


@pytest.fixture
def home(tmp_path: Path, sim_factory: Callable[..., Any]) -> Iterator[tuple[Any, Any]]:
    from pmk_nb.ui.home.screen import HomeScreen

    yaml = write_test_map(room_grid(12.0, 6.0), tmp_path / "maps", "hall")
    sim = sim_factory(map_yaml=yaml, start_pose=(1.0, 3.0, 0.0))
    profiles = ProfileStore(tmp_path / "profiles.json", secrets=False)
    profiles.save(ChairProfile(name="sim", host="127.0.0.1", port=sim.port))
    ctx = AppContext(MapsFolder(tmp_path / "maps"), profiles, config_dir=tmp_path / "cfg")
    ctx.set_current_map("hall", yaml, None)
    screen = HomeScreen(ctx, canvas_width=320, canvas_height=240, fps=10)
    try:
        yield screen, sim
    finally:
        screen.close()
        ctx.close()


def _subscribers(sim: Any, topic: str) -> int:
    entry = sim.bridge.topics.get(topic) if sim.bridge is not None else None
    return sum(len(sub.by_id) for sub in entry.subs.values()) if entry is not None else 0  # subscriber ids


@pytest.mark.slow
def test_plots_topics_and_the_planned_path(home: tuple[Any, Any]) -> None:
    screen, sim = home
    plots: PlotsPanel = screen.plots
    assert plots.widget.layout.display == "none" and plots.toggle in screen.ui.controls.children
    assert screen.start_preview()
    link = screen.ctx.link()
    assert wait_ticking(lambda: screen.connection_state()[0] == "live", 15.0, screen.refresh_info)
    link.navigate_to(10.0, 3.0, 0.0)  # the chair drives: speed samples, and the sim publishes /plan
    assert wait_ticking(lambda: len(plots.history) >= 6, 15.0, screen.refresh_info), len(plots.history)
    assert plots.draws == 0  # closed: nothing drawn
    assert wait_ticking(lambda: screen.path.points.shape[0] >= 2, 15.0, screen.refresh_info), "no planned path"
    assert abs(screen.path.points[-1][0] - 10.0) < 0.2  # to the goal
    moved = lambda: plots.history.window(0.0)[:, 1].max() > 0.1  # noqa: E731
    assert wait_ticking(moved, 15.0, screen.refresh_info), plots.history.window(0.0)

    plots.toggle.value = True
    assert plots.widget.layout.display == "" and plots.draws >= 1
    listed = lambda: "topics from" in plots.topics.source.value or "known" in plots.topics.source.value  # noqa: E731
    assert wait_ticking(listed, 15.0, screen.refresh_info), plots.topics.source.value
    assert "from rosapi" in plots.topics.source.value
    # the TF tree on its own /tf subscription (this link's pose comes from odometry: it has none)
    assert wait_ticking(lambda: "odom → <b>base_link</b>" in plots.tf.table.value, 15.0, screen.refresh_info)
    # the plan where this chair publishes it (ROS 1: move_base's planner topic); no /plan is guessed into being
    assert {"/odom", "/scan", sim.names.plan_topic} <= set(plots.topics.types), sorted(plots.topics.types)
    assert sim.names.plan_topic == "/plan" or "/plan" not in plots.topics.types
    before = _subscribers(sim, "/scan")
    plots.topics.list.value = "/scan"
    assert wait_ticking(lambda: "ranges" in plots.topics.message.value, 10.0, screen.refresh_info)
    assert "more of" in plots.topics.message.value  # 360 ranges shortened
    assert wait_ticking(lambda: "Hz" in plots.topics.info.value, 10.0, screen.refresh_info), plots.topics.info.value
    assert _subscribers(sim, "/scan") == before + 1  # one extra, throttled subscription
    plots.toggle.value = True  # (still open) inspect /odom, which the link itself streams, then close
    plots.topics.list.value = "/odom"
    assert wait_ticking(lambda: "twist" in plots.topics.message.value, 10.0, screen.refresh_info)
    plots.toggle.value = False  # closing ends the inspector's subscriptions, and only those
    assert plots.tf.watch is None
    assert wait_ticking(lambda: _subscribers(sim, "/scan") == before, 5.0, lambda: None)
    seen = link.latest_odom()
    assert wait_ticking(lambda: link.latest_odom() is not seen, 5.0, lambda: None), "the link's /odom stream died"
    draws = plots.draws
    for _ in range(4):
        screen.refresh_info()
    assert plots.draws == draws  # closed: no redraws
    plots.toggle.value = True
    plots.topics._on_pick({"new": "/made-up"})  # a value the list never offered: nothing subscribed
    assert plots.topics.probe is None
