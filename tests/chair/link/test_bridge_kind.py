"""Issue 24: the connection test (Settings, `pmk chair test`) says when the chair's rosbridge keeps
a lost tablet's goals and ignores cancels (rosbridge_suite, told apart through rosapi)."""

from __future__ import annotations

import pytest

from pmk_nb.chair.link.query.bridge_kind import detect_bridge
from pmk_nb.sim import BRIDGE_MODES


@pytest.mark.parametrize("bridge", BRIDGE_MODES)
def test_the_connection_test_names_the_bridge_and_warns(sim_factory, link_factory, bridge: str) -> None:
    sim = sim_factory(ros="ros2", bridge=bridge)
    link = link_factory(sim)
    report = link.test_connection(timeout=5.0)
    assert report.ok and report.bridge is not None
    official = bridge == "official"
    assert report.bridge.name == ("rosbridge_suite" if official else "other")
    assert report.bridge.ignores_cancels is official and report.bridge.keeps_lost_goals is official
    assert report.bridge.goals_in_new_thread is (False if official else None)
    assert any("send_action_goals_in_new_thread" in note for note in report.notes) is official


def test_a_ros1_chair_is_not_asked(sim_factory, link_factory) -> None:
    link = link_factory(sim_factory(ros="ros1"))
    report = link.test_connection(timeout=5.0)
    assert report.ok and report.bridge is None
    assert detect_bridge(link).name == "other"  # ROS 1 rosapi: no rosapi_params helper node
