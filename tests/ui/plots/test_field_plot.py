"""Plot anything (issue 40): any numeric field of any topic of the simulated chair, several series, a
time window and Pause, through the real link and widgets; one throttled subscription per plotted topic,
gone with its last series."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest

from pmk_nb.ui.plots.field_plot import FieldPlot
from tests.fixtures_sim import room_grid
from tests.helpers import wait_ticking
from tests.ui.plots.test_plots import _subscribers


@pytest.mark.slow
@pytest.mark.parametrize("ros", ["ros2", "ros1"])
def test_fields_of_two_topics_plotted_paused_and_removed(
    ros: str, sim_factory: Callable[..., Any], link_factory: Callable[[Any], Any]
) -> None:
    sim = sim_factory(grid=room_grid(12.0, 6.0), ros=ros, start_pose=(1.0, 3.0, 0.0))
    link = link_factory(sim)
    plot = FieldPlot()
    plot.attach(link)
    plot.set_topics(link.discovery.topics(timeout=5.0))
    assert not plot.add("/odom", "twist.twist.linear.x; drop")  # a malformed path: refused in words
    assert "field" in plot.status.value and plot.subs == {}
    assert not plot.add("/made-up", "x") and "topic" in plot.status.value
    plot.topic.value = "/odom"
    assert wait_ticking(lambda: "twist.twist.linear.x" in plot.field.options, 10.0, plot.tick), plot.status.value
    assert "pose.covariance[35]" in plot.field.options and "header.stamp" in plot.field.options
    before = _subscribers(sim, "/odom")
    assert plot.add("/odom", "twist.twist.linear.x") and plot.add("/odom", "pose.pose.position.x")
    assert plot.add("/scan", "range_max")  # another topic: its own subscription
    assert wait_ticking(lambda: _subscribers(sim, "/odom") == before + 1, 5.0)  # two fields, one subscription
    goal = link.navigate_to(3.5, 3.0, 0.0)
    ring = plot.subs["/odom"].rings["pose.pose.position.x"]
    assert wait_ticking(lambda: len(ring) > 5 and ring.window(0.0)[:, 1].max() > 1.5, 20.0, plot.tick)
    assert wait_ticking(lambda: len(plot.subs["/scan"].rings["range_max"]) > 2, 10.0, plot.tick)
    plot.redraw()
    assert "/odom pose.pose.position.x = " in plot.legend.value and "range_max = 10" in plot.legend.value
    plot.window.value = 30.0
    plot.pause.value = True
    draws, legend = plot.draws, plot.legend.value
    assert "paused" in legend
    for _ in range(5):
        plot.tick(plot.paused_at + 10.0)  # paused: the chart does not move on
    assert plot.draws == draws and plot.legend.value == legend
    plot.pause.value = False
    plot.tick()
    assert plot.draws > draws and "live" in plot.legend.value
    # rosbridge_suite holds a socket's other ops while an action goal runs on it (so does the simulator)
    assert wait_ticking(lambda: goal.progress().done, 20.0, plot.tick), goal.progress()
    during = _subscribers(sim, "/odom")  # the goal follows /odom on the link's own subscription too
    plot.remove("/odom twist.twist.linear.x")
    assert "/odom" in plot.subs and _subscribers(sim, "/odom") == during  # its other series goes on
    plot.remove("/odom pose.pose.position.x")
    assert "/odom" not in plot.subs
    assert wait_ticking(lambda: _subscribers(sim, "/odom") == during - 1, 5.0)
    scans = _subscribers(sim, "/scan")
    plot.close()
    assert wait_ticking(lambda: _subscribers(sim, "/scan") == scans - 1, 5.0)
