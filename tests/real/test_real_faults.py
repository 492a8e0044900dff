"""Real-stack tier, issue 9 faults 1, 6 and 10 and the link's reconnects: the dashboard's link against
rosbridge-server-rs (with and without rosapi) bridging the project's rclpy nodes."""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Iterator

import pytest

from pmk_nb.chair.link import ChairLink, LinkState
from pmk_nb.chair.link.query.discovery import RosapiMissing
from tests import fixtures_ros2
from tests.fixtures_ros2 import RealChair, free_port
from tests.fixtures_sim import room_grid, write_test_map
from tests.helpers import wait_until

# the real-stack fixtures (not in the root conftest's plugins)
ros2_stack, real_chair = fixtures_ros2.ros2_stack, fixtures_ros2.real_chair
INFO = ("/map_server/map_info", "map_server_pmk/srv/MapInfo")


def start(chair: RealChair, *, rosapi: bool, sim_node: bool = True, map_server: tuple[str, ...] = ()) -> None:
    """Bridge + map server on an 8 m x 6 m room (160x120) [+ the sim node], all discovered."""
    write_test_map(room_grid(8.0, 6.0), chair.maps, "room")
    chair.start_bridge(rosapi=rosapi)
    chair.start_map_server("room", *map_server)
    if sim_node:
        chair.start_sim_node("--map", "room")
    if "map_info" in " ".join(map_server):
        chair.wait_service("/map_server/load_map", "nav2_msgs/srv/LoadMap", {"map_url": "room.yaml"})
    else:
        chair.wait_service(*INFO)


@pytest.fixture
def links() -> Iterator[list[ChairLink]]:
    made: list[ChairLink] = []
    yield made
    for link in made:
        link.close()


def test_connection_without_rosapi_is_a_success_that_says_so(real_chair: RealChair, links) -> None:
    """Fault 1: connected + map info shown; "without rosapi" in plain words, never the bridge's raw text."""
    start(real_chair, rosapi=False, sim_node=False)
    link = ChairLink("127.0.0.1", real_chair.port)
    links.append(link)
    report = link.test_connection(timeout=10)
    assert report.ok, report.reason
    assert (report.map_info.width, report.map_info.height) == (160, 120)
    assert report.rosapi is False
    assert len(report.notes) == 1 and "without rosapi" in report.notes[0]
    assert "/map_server/load_map" in report.notes[0]
    with pytest.raises(RosapiMissing) as err:
        link.topics_of_type("nav_msgs/Odometry")
    assert "runs without rosapi" in str(err.value) and "absent from ROS graph" not in str(err.value)
    assert "absent from ROS graph" in err.value.answer  # the bridge's own words stay available


def test_connection_with_rosapi_and_discovery(real_chair: RealChair, links) -> None:
    """rosapi_msgs built by `make ros2`: the bridge answers rosapi; topics, services, reload service."""
    start(real_chair, rosapi=True)
    link = ChairLink("127.0.0.1", real_chair.port)
    links.append(link)
    report = link.test_connection(timeout=10)
    assert report.ok and report.rosapi is True and report.notes == ()
    assert report.ros_version == 2  # from rosapi's get_time spelling (sec/nanosec)
    assert (report.map_info.width, report.map_info.height) == (160, 120)
    wait_until(lambda: "/odom" in link.discovery.topics(), 15, "the sim node's topics in rosapi")
    assert link.topics_of_type("nav_msgs/Odometry") == ["/odom"]
    assert link.topics_of_type("sensor_msgs/LaserScan") == ["/scan"]
    assert "/map_metadata" in link.discovery.topics()
    services = link.services()
    assert {"/map_server/load_map", "/map_update", "/map_server/map_info"} <= set(services)
    found = link.detect_reload_service()
    assert (found.name, found.kind) == ("/map_server/load_map", "nav2")
    assert link.discovery.service_type("/map_update") == "map_server_pmk/srv/MapUpdate"


def test_reload_without_rosapi_tries_the_known_names(real_chair: RealChair, links) -> None:
    """Fault 1: no rosapi, only /map_update offered: /change_map and /map_server/load_map are absent
    (the bridge says so at once), /map_update loads the map."""
    start(real_chair, rosapi=False, sim_node=False, map_server=("--services", "map_update"))
    write_test_map(room_grid(5.0, 4.0), real_chair.maps, "small")
    link = ChairLink("127.0.0.1", real_chair.port)
    links.append(link)
    link.connect(10)
    used = link.reload_map(str(real_chair.maps / "small.yaml"))
    assert (used.name, used.kind) == ("/map_update", "mapupdate")
    assert link.discovery.rosapi is False
    facts = link.map_facts(5)
    assert facts is not None and facts.path == str(real_chair.maps / "small.yaml")
    assert (facts.info.width, facts.info.height) == (100, 80)


def test_map_info_without_metadata_nor_rosapi_learns_the_source(real_chair: RealChair, links) -> None:
    """Fault 10: a Nav2-like server (no /map_metadata, no MapInfo) behind a bridge without rosapi.
    /map is asked for after a short head start for /map_metadata, and the next call goes straight to it."""
    start(real_chair, rosapi=False, sim_node=False, map_server=("--without", "map_metadata,map_info"))
    link = ChairLink("127.0.0.1", real_chair.port)
    links.append(link)
    link.connect(10)
    info = link.map_info(10)
    assert (info.width, info.height) == (160, 120)
    assert link.map_facts(5) is None  # no MapInfo service: remembered, not asked again
    plan = link._maps._plan(5.0)
    assert [(name, delay) for name, _type, delay in plan] == [("/map", 0.0)]
    assert link.map_info(5).width == 160


class DelayingProxy:
    """A TCP proxy in front of the bridge that holds the server's bytes of its FIRST connection for
    ``delay`` s after the websocket handshake: a bridge too busy to answer (fault 6)."""

    def __init__(self, target_port: int, delay: float) -> None:
        self.port, self.target, self.delay = free_port(), target_port, delay
        self.loop = asyncio.new_event_loop()
        self.connections = 0
        ready = threading.Event()
        threading.Thread(target=self._run, args=(ready,), daemon=True, name="delaying-proxy").start()
        ready.wait(5)

    def _run(self, ready: threading.Event) -> None:
        asyncio.set_event_loop(self.loop)
        server = self.loop.run_until_complete(asyncio.start_server(self._handle, "127.0.0.1", self.port))
        ready.set()
        try:
            self.loop.run_until_complete(server.serve_forever())
        except RuntimeError:  # stopped by close()
            pass

    async def _handle(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        self.connections += 1
        slow = self.connections == 1
        up_reader, up_writer = await asyncio.open_connection("127.0.0.1", self.target)

        async def pipe(src: asyncio.StreamReader, dst: asyncio.StreamWriter, hold: bool) -> None:
            first = True
            while data := await src.read(65536):
                if hold and not first:
                    await asyncio.sleep(self.delay)
                    hold = False
                first = False
                dst.write(data)
                await dst.drain()
            dst.close()

        await asyncio.gather(pipe(reader, up_writer, False), pipe(up_reader, writer, slow), return_exceptions=True)

    def close(self) -> None:
        self.loop.call_soon_threadsafe(self.loop.stop)


def test_a_late_rosbridge_answer_is_not_called_not_a_rosbridge(real_chair: RealChair, links) -> None:
    """Fault 6: the bridge answers rosapi late (busy). Within the timeout: connected; beyond it:
    "timed out" naming a busy bridge, never "not a rosbridge server"."""
    start(real_chair, rosapi=True, sim_node=False)
    proxy = DelayingProxy(real_chair.port, delay=2.0)
    try:
        link = ChairLink("127.0.0.1", proxy.port)
        links.append(link)
        report = link.test_connection(timeout=1.0)
        assert not report.ok
        assert report.reason.startswith("timed out") and "busy rosbridge" in report.reason, report.reason
        assert "not a rosbridge server:" not in report.reason
        proxy.connections = 0  # the next probe is slow again, but within the timeout
        report = link.test_connection(timeout=8.0)
        assert report.ok, report.reason
        assert report.ros_version == 2 and report.map_info.width == 160
    finally:
        proxy.close()


def test_reconnects_after_the_bridge_and_after_the_node_are_killed(real_chair: RealChair, links) -> None:
    start(real_chair, rosapi=False)
    link = ChairLink("127.0.0.1", real_chair.port, reconnect_initial=0.2, reconnect_max=1.0, stale_after=1.0)
    links.append(link)
    link.connect(10)
    link.start_streams()
    wait_until(lambda: link.latest_odom() is not None, 15, "odometry")

    real_chair.kill("bridge")
    wait_until(lambda: link.state is LinkState.CONNECTING, 10, "the link noticing the bridge is gone")
    real_chair.start_bridge(rosapi=False)  # same port
    wait_until(lambda: link.state is LinkState.CONNECTED, 20, "the link reconnecting to the new bridge")
    seen = link.message_counts.get("odom", 0)
    wait_until(lambda: link.message_counts.get("odom", 0) > seen + 10, 20, "odometry through the new bridge")

    real_chair.kill("sim_node")
    wait_until(lambda: link.state is LinkState.STALE, 10, "stale once the node is gone")
    real_chair.start_sim_node("--map", "room")
    seen = link.message_counts.get("odom", 0)
    wait_until(lambda: link.message_counts.get("odom", 0) > seen + 10, 30, "odometry from the restarted node")
    wait_until(lambda: link.state is LinkState.CONNECTED, 10, "connected again")


def test_settings_screen_without_rosapi_shows_connected_and_says_why_pickers_are_empty(
    real_chair: RealChair, tmp_path
) -> None:
    """Fault 1 on the Settings screen: "Connected", the map's size, and the plain-word note; never the
    "Disconnected: /rosapi/topics … type is required" the issue saw."""
    from pmk_nb.ui.settings.screen import SettingsScreen
    from tests.helpers import app_context

    start(real_chair, rosapi=False, sim_node=False)
    with app_context(tmp_path) as ctx:
        screen = SettingsScreen(ctx)
        for key, value in {
            "name": "Real",
            "host": "127.0.0.1",
            "port": str(real_chair.port),
            "ssh_user": "pmk",
        }.items():
            screen.fields[key].value = value
        screen.test_button.click()
        wait_until(lambda: screen.state not in ("Connecting", "Disconnected"), 30, "the connection test")
        assert screen.state == "Connected", screen.status.value
        assert "<b>160</b>" in screen.map_info.value and "<b>120</b>" in screen.map_info.value
        assert "runs without rosapi" in screen.map_info.value
        assert "type is required" not in screen.status.value + screen.map_info.value
