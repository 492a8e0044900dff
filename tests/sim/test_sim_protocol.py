"""rosbridge v2 conformance of the simulator: raw WebSocket JSON for errors, roslibpy for the rest."""

from __future__ import annotations

import asyncio
import json
import socket
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest
import roslibpy
from websockets.sync.client import ClientConnection, connect

from pmk_nb.sim.session import png_decode
from tests.fixtures_sim import room_grid, wait_until


@pytest.fixture
def raw(sim_chair) -> Iterator[ClientConnection]:
    with connect(sim_chair.url, open_timeout=5) as ws:
        yield ws


def send(ws: ClientConnection, **msg: Any) -> None:
    ws.send(json.dumps(msg))


def recv_until(ws: ClientConnection, pred: Callable[[dict], bool], timeout: float = 3.0) -> dict:
    deadline = time.monotonic() + timeout
    while True:
        left = deadline - time.monotonic()
        if left <= 0:
            raise AssertionError("no matching message before the timeout")
        msg = json.loads(ws.recv(timeout=left))
        if pred(msg):
            return msg


def status_for(ws: ClientConnection, op_id: str) -> dict:
    return recv_until(ws, lambda m: m.get("op") == "status" and m.get("id") == op_id)


@pytest.mark.parametrize(
    ("request_", "needle"),
    [
        ({"op": "frobnicate", "id": "e1"}, "Unknown operation"),
        ({"op": "subscribe", "id": "e2"}, "missing required field(s) topic"),
        ({"op": "subscribe", "id": "e3", "topic": "/nope"}, "cannot infer topic type"),
        ({"op": "subscribe", "id": "e4", "topic": "/odom", "type": "sensor_msgs/LaserScan"}, "has type"),
        ({"op": "publish", "id": "e5", "topic": "/nope", "msg": {}}, "does not exist"),
        ({"op": "publish", "id": "e6", "topic": "/cmd_vel", "msg": {"data": "hi"}}, "does not conform"),
        ({"op": "advertise", "id": "e7", "topic": "/odom", "type": "std_msgs/String"}, "already has type"),
        ({"op": "advertise", "id": "e8", "topic": "/x", "type": "not a type"}, "cannot resolve type"),
        ({"op": "call_service", "id": "e9"}, "missing required field(s) service"),
    ],
)
def test_bad_requests_get_error_status(raw, request_, needle):
    raw.send(json.dumps(request_))
    status = status_for(raw, request_["id"])
    assert status["level"] == "error"
    assert needle in status["msg"]


def test_garbage_is_reported_and_connection_survives(raw):
    raw.send("{not json")
    status = recv_until(raw, lambda m: m.get("op") == "status")
    assert status["level"] == "error" and "JSON" in status["msg"]
    send(raw, op="call_service", id="c1", service="/rosapi/topics")
    assert recv_until(raw, lambda m: m.get("op") == "service_response")["result"] is True


def test_unknown_service_fails_with_response_and_status(raw):
    send(raw, op="call_service", id="u1", service="/no_such_service", args={})
    seen = [recv_until(raw, lambda m: m.get("id") == "u1"), recv_until(raw, lambda m: m.get("id") == "u1")]
    ops = {m["op"]: m for m in seen}
    assert ops["status"]["level"] == "error"
    assert ops["service_response"]["result"] is False
    assert "does not exist" in ops["service_response"]["values"]


def test_service_response_carries_id_values_result(raw):
    send(raw, op="call_service", id="t1", service="/rosapi/topic_type", args={"topic": "/odom"})
    reply = recv_until(raw, lambda m: m.get("op") == "service_response")
    assert reply == {
        "op": "service_response",
        "service": "/rosapi/topic_type",
        "values": {"type": "nav_msgs/Odometry"},
        "result": True,
        "id": "t1",
    }


def test_warnings_only_after_set_level(raw):
    send(raw, op="unsubscribe", id="w1", topic="/odom")  # not subscribed: a warning, hidden at level error
    send(raw, op="set_level", level="warning")
    send(raw, op="unsubscribe", id="w2", topic="/odom")
    status = recv_until(raw, lambda m: m.get("op") == "status")
    assert status["id"] == "w2" and status["level"] == "warning"


def test_latched_map_reaches_late_subscriber(sim_chair, ros_factory):
    time.sleep(0.3)  # published long before anyone subscribes
    ros = ros_factory(sim_chair)
    got: list[dict] = []
    roslibpy.Topic(ros, "/map", "nav_msgs/OccupancyGrid").subscribe(got.append)
    assert wait_until(lambda: len(got) == 1, 3.0)
    grid = sim_chair.grid
    assert got[0]["info"]["width"] == grid.width and got[0]["info"]["height"] == grid.height
    assert len(got[0]["data"]) == grid.width * grid.height
    meta: list[dict] = []
    roslibpy.Topic(ros, "/map_metadata", "nav_msgs/MapMetaData").subscribe(meta.append)
    assert wait_until(lambda: len(meta) == 1, 3.0)
    assert meta[0]["resolution"] == pytest.approx(grid.resolution)


def _stamp_s(msg: dict) -> float:
    stamp = msg["header"]["stamp"]  # ROS 1 secs/nsecs, ROS 2 sec/nanosec
    return stamp.get("secs", stamp.get("sec", 0)) + 1e-9 * stamp.get("nsecs", stamp.get("nanosec", 0))


@pytest.mark.slow
def test_throttle_rate_limits_messages(sim_chair, ros_factory):
    """At most one message per throttle period, judged by the messages' own stamps (when the server
    sent them): arrival times bunch on a loaded machine (a make test run saw two 77 ms apart)."""
    ros = ros_factory(sim_chair)
    stamps: list[float] = []
    roslibpy.Topic(ros, "/odom", "nav_msgs/Odometry", throttle_rate=200).subscribe(
        lambda msg: stamps.append(_stamp_s(msg))
    )
    assert wait_until(lambda: len(stamps) >= 1, 3.0)
    first, t0 = len(stamps), time.monotonic()
    time.sleep(1.5)
    rate = (len(stamps) - first) / (time.monotonic() - t0)  # the sleep's real span (it overshoots under load)
    assert 3.0 <= rate <= 6.0, f"throttle 200 ms should give ~5 Hz, got {rate:.1f} Hz"
    gaps = [b - a for a, b in zip(stamps[first:], stamps[first + 1 :], strict=False)]
    assert min(gaps) > 0.15, gaps


@pytest.mark.slow
def test_queue_length_with_throttle_sends_buffered_messages(raw):
    send(raw, op="subscribe", id="q", topic="/odom", throttle_rate=100, queue_length=1)
    t0 = time.monotonic()
    count = 0
    while time.monotonic() - t0 < 1.0:
        if json.loads(raw.recv(timeout=2.0)).get("op") == "publish":
            count += 1
    assert 7 <= count <= 13, f"queue_length 1 + throttle 100 ms should give ~10 msgs/s, got {count}"


def test_png_compression_round_trip(raw):
    send(raw, op="subscribe", id="p", topic="/map_metadata", compression="png")
    packed = recv_until(raw, lambda m: m.get("op") == "png")
    inner = json.loads(png_decode(packed["data"]))
    assert inner["op"] == "publish" and inner["topic"] == "/map_metadata"
    assert inner["msg"]["width"] > 0


def test_outgoing_fragments_reassemble(raw):
    send(raw, op="subscribe", id="f", topic="/map", fragment_size=1000)
    first = recv_until(raw, lambda m: m.get("op") == "fragment")
    pieces = {first["num"]: first["data"]}
    while len(pieces) < first["total"]:
        frag = recv_until(raw, lambda m: m.get("op") == "fragment" and m.get("id") == first["id"])
        pieces[frag["num"]] = frag["data"]
    whole = json.loads("".join(pieces[i] for i in range(first["total"])))
    assert whole["topic"] == "/map" and whole["msg"]["info"]["width"] > 0


def test_incoming_fragments_are_reassembled(raw):
    text = json.dumps({"op": "call_service", "id": "fr", "service": "/rosapi/services"})
    parts = [text[i : i + 20] for i in range(0, len(text), 20)]
    for n, part in enumerate(parts):
        send(raw, op="fragment", id="in1", data=part, num=n, total=len(parts))
    reply = recv_until(raw, lambda m: m.get("op") == "service_response")
    assert reply["id"] == "fr" and "/rosapi/services" in reply["values"]["services"]


def test_client_to_client_topic_and_service(sim_chair, ros_factory):
    a, b = ros_factory(sim_chair), ros_factory(sim_chair)
    heard: list[dict] = []
    roslibpy.Topic(b, "/chatter", "std_msgs/String").subscribe(heard.append)
    talker = roslibpy.Topic(a, "/chatter", "std_msgs/String")
    assert wait_until(lambda: "/chatter" in sim_chair.bridge.topics, 3.0)
    talker.publish(roslibpy.Message({"data": "hello"}))
    assert wait_until(lambda: heard == [{"data": "hello"}], 3.0)

    def add_two(request: dict, response: dict) -> bool:
        response["sum"] = request["a"] + request["b"]
        return True

    roslibpy.Service(a, "/add_two_ints", "rospy_tutorials/AddTwoInts").advertise(add_two)
    assert wait_until(lambda: "/add_two_ints" in sim_chair.bridge.services, 3.0)
    result = roslibpy.Service(b, "/add_two_ints", "rospy_tutorials/AddTwoInts").call(
        roslibpy.ServiceRequest({"a": 2, "b": 40}), timeout=5
    )
    assert result["sum"] == 42


@pytest.mark.slow
def test_slow_client_does_not_block_others(sim_factory, ros_factory):
    sim = sim_factory(grid=room_grid(6.0, 4.0), scan_rate=40.0, rays=1080)
    # a client with a tiny receive buffer that subscribes to everything and never reads
    sock = socket.socket()
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    sock.connect(("127.0.0.1", sim.port))
    with connect(sim.url, sock=sock, open_timeout=5, close_timeout=0.5, max_size=None) as idle:
        for topic in ("/scan", "/odom", "/tf"):
            send(idle, op="subscribe", topic=topic)
        ros = ros_factory(sim)
        odom: list[float] = []
        roslibpy.Topic(ros, "/odom", "nav_msgs/Odometry").subscribe(lambda _: odom.append(time.monotonic()))
        assert wait_until(lambda: len(odom) > 0, 3.0)
        start = len(odom)
        time.sleep(1.5)
        assert len(odom) - start >= 40, "a stalled client slowed down the others"


def test_client_queue_drops_oldest_when_the_socket_stalls():
    from pmk_nb.sim.session import ClientSession

    class StalledSocket:  # a peer whose TCP window never opens: send() never completes
        def __init__(self) -> None:
            self.sent: list[str] = []

        async def send(self, text: str) -> None:
            self.sent.append(text)
            await asyncio.Event().wait()

    async def scenario() -> tuple[ClientSession, StalledSocket]:
        ws = StalledSocket()
        session = ClientSession(1, ws, max_queue=3)  # type: ignore[arg-type]
        writer = asyncio.create_task(session.run_writer())
        session.send_data("m0")
        await asyncio.sleep(0.01)  # m0 is now stuck in send()
        for i in range(1, 8):
            session.send_data(f"m{i}")
        session.send_control("status")
        writer.cancel()
        return session, ws

    session, ws = asyncio.run(scenario())
    assert ws.sent == ["m0"]
    assert list(session._data) == ["m5", "m6", "m7"] and session.dropped == 4
    assert list(session._control) == ["status"]


def test_a_parked_chair_scans_without_casting_again(sim_factory, ros_factory):
    """Same world, same pose, same laser: the same ranges, sent again without a new ray cast (ten
    parked classroom chairs cast 50 scans a second for nothing); a chair that moves casts again."""
    sim = sim_factory(grid=room_grid(6.0, 4.0), scan_rate=20.0)
    laser = sim.engine.laser
    casts: list[float] = []
    real_cast = laser.cast

    def counting_cast(*args, **kwargs):
        casts.append(time.monotonic())
        return real_cast(*args, **kwargs)

    laser.cast = counting_cast
    ros = ros_factory(sim)
    scans: list[list[float | None]] = []
    roslibpy.Topic(ros, "/scan", "sensor_msgs/LaserScan").subscribe(lambda m: scans.append(m["ranges"]))
    assert wait_until(lambda: len(scans) >= 8, 10.0), "scans keep coming from a parked chair"
    assert len(casts) <= 2, f"{len(casts)} casts for {len(scans)} scans of a parked chair"
    assert all(s == scans[0] for s in scans), "a parked chair's scans are all the same"
    twist = {"linear": {"x": 0.0, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": 0.8}}
    cmd = roslibpy.Topic(ros, "/cmd_vel", "geometry_msgs/Twist")
    before = len(casts)
    deadline = time.monotonic() + 10.0
    while len(casts) < before + 2 and time.monotonic() < deadline:
        cmd.publish(roslibpy.Message(twist))
        time.sleep(0.1)
    assert len(casts) >= before + 2, "a turning chair casts again"
    assert scans[-1] != scans[0], "and its scans change"
