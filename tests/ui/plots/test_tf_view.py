"""The TF tree view (issue 40) against the simulated chair (real link, real widgets): the simulator's
map -> odom -> base_link appear with their parents and a rate, on subscriptions of the view's own that
end when it is detached (the link's own /tf stream, here its pose source, goes on)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest

from pmk_nb.chair.link import ChairLink
from pmk_nb.ui.plots.tf_view import TfTreeView
from tests.fixtures_sim import room_grid
from tests.helpers import wait_ticking
from tests.ui.plots.test_plots import _subscribers


@pytest.mark.slow
@pytest.mark.parametrize("ros", ["ros2", "ros1"])
def test_the_simulated_chairs_frames_and_parents_appear(ros: str, sim_factory: Callable[..., Any]) -> None:
    sim = sim_factory(grid=room_grid(12.0, 6.0), ros=ros, start_pose=(1.0, 3.0, 0.0))
    link = ChairLink("127.0.0.1", sim.port, pose_source="tf")
    try:
        link.connect(timeout=10.0)
        link.start_streams()
        assert wait_ticking(lambda: _subscribers(sim, "/tf") == 1, 10.0), "the link's own /tf subscription"
        view = TfTreeView()
        assert view.table.value == ""
        view.attach(link)
        assert wait_ticking(lambda: _subscribers(sim, "/tf") == 2, 10.0), _subscribers(sim, "/tf")
        parents = lambda: {r.frame: r.parent for r in view.rows}  # noqa: E731
        want = {"map": None, "odom": "map", "base_link": "odom"}
        hz = lambda: all(r.rate_hz for r in view.rows if r.parent)  # noqa: E731
        assert wait_ticking(lambda: parents() == want and hz(), 20.0, view.tick), view.rows
        assert [(r.frame, r.depth) for r in view.rows] == [("map", 0), ("odom", 1), ("base_link", 2)]
        table = view.table.value
        assert "map → <b>odom</b>" in table and "odom → <b>base_link</b>" in table and " Hz · " in table
        assert "3 frames, 1 tree" in view.summary.value
        view.attach(None)  # the panel closed: the view's subscriptions end, the link's goes on
        assert wait_ticking(lambda: _subscribers(sim, "/tf") == 1, 10.0), _subscribers(sim, "/tf")
        assert view.watch is None and view.table.value == ""
        seen = link.latest_pose()
        assert wait_ticking(lambda: link.latest_pose() is not seen, 10.0), "the link's /tf stream died"
    finally:
        link.close()
