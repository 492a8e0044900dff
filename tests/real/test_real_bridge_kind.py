"""Real-stack tier, issue 24: rosbridge-server-rs is not taken for rosbridge_suite (no cancel
warning), as the simulator's rs mode assumes: its rosapi lists no ``/rosapi_params`` helper node."""

from __future__ import annotations

from pmk_nb.chair.link import ChairLink
from pmk_nb.chair.link.query.bridge_kind import detect_bridge
from pmk_nb.sim.bridge_modes import FACTS
from tests import fixtures_ros2
from tests.fixtures_ros2 import RealChair
from tests.real.test_real_faults import start

ros2_stack, real_chair = fixtures_ros2.ros2_stack, fixtures_ros2.real_chair


def test_rosbridge_server_rs_is_not_rosbridge_suite(real_chair: RealChair) -> None:
    start(real_chair, rosapi=True, sim_node=False)
    link = ChairLink("127.0.0.1", real_chair.port)
    try:
        report = link.test_connection(timeout=10)
        assert report.ok, report.reason
        assert report.bridge is not None and report.bridge.name == "other" and not report.bridge.ignores_cancels
        assert not any("send_action_goals_in_new_thread" in note for note in report.notes)
        nodes = link.call("/rosapi/nodes", "rosapi_msgs/srv/Nodes", {}, 5.0)["nodes"]
        assert set(FACTS["rs"].nodes) <= set(nodes) and "/rosapi_params" not in nodes  # what the sim lists
        assert detect_bridge(link).name == "other"
    finally:
        link.close()
