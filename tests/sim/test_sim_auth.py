"""rosbridge authentication (rosauth's ``auth`` op) on the simulator and on the link (issue 38, item 2).

A seat's chair in ``pmk hub`` requires its student's secret: a client that sends any other op first, or
an ``auth`` with a wrong MAC, is refused and its socket closed; roslibpy's own ``authenticate`` with the
right MAC (sha512 of secret + client + dest + rand + t + level + end, computed here by hand) is served.
"""

from __future__ import annotations

import hashlib
import json
import threading
import time
from pathlib import Path
from typing import Any

import pytest
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import connect

from pmk_nb.chair.link import ChairLink
from pmk_nb.chair.link.transport.bridge_auth import BridgeAuth, BridgeAuthError
from pmk_nb.chair.link.transport.ros import LinkRos
from pmk_nb.rosauth import granted
from pmk_nb.sim import SimChair
from tests.fixtures_sim import sim_factory, wait_until  # noqa: F401

SECRET = "s3cret-of-student-a"


def _mac(secret: str, rand: str, t: int, end: int) -> str:
    text = f"{secret}127.0.0.1127.0.0.1{rand}{t}user{end}"
    return hashlib.sha512(text.encode()).hexdigest()


def _closed_after(port: int, first: dict[str, Any]) -> bool:
    """Send ``first`` then subscribe to /odom: True when the chair closes the socket without serving it."""
    with connect(f"ws://127.0.0.1:{port}", open_timeout=5) as ws:
        deadline = time.monotonic() + 10
        try:
            ws.send(json.dumps(first))
            # The chair may close the socket before the second frame goes out: that is a refusal too.
            ws.send(json.dumps({"op": "subscribe", "topic": "/odom", "type": "nav_msgs/Odometry"}))
            while time.monotonic() < deadline:
                msg = json.loads(ws.recv(timeout=deadline - time.monotonic()))
                if msg.get("op") == "publish":
                    return False
        except ConnectionClosed as err:
            return err.rcvd is not None and err.rcvd.code == 1008
    return False


def test_ops_without_auth_are_refused_and_the_socket_closed(sim_factory: Any) -> None:  # noqa: F811
    sim: SimChair = sim_factory(auth_secret=SECRET)
    assert _closed_after(sim.port, {"op": "subscribe", "topic": "/odom", "type": "nav_msgs/Odometry"})


def test_a_wrong_mac_is_refused(sim_factory: Any) -> None:  # noqa: F811
    sim: SimChair = sim_factory(auth_secret=SECRET)
    t = int(time.time())
    op = {"op": "auth", "client": "127.0.0.1", "dest": "127.0.0.1", "rand": "r", "t": t, "level": "user"}
    op |= {"end": t + 60, "mac": _mac("another student's secret", "r", t, t + 60)}
    assert _closed_after(sim.port, op)


def test_a_stale_time_is_refused_even_with_the_right_secret() -> None:
    t = 1_800_000_000  # the time is an input: a minute late is refused, a second late is not
    op = {"op": "auth", "client": "127.0.0.1", "dest": "127.0.0.1", "rand": "r", "t": t, "level": "user"}
    op |= {"end": t + 3600, "mac": _mac(SECRET, "r", t, t + 3600)}
    assert not granted(SECRET, op, now=t + 60)
    assert granted(SECRET, op, now=t + 1)


def test_roslibpy_authenticate_with_the_right_mac_is_served(sim_factory: Any) -> None:  # noqa: F811
    import roslibpy

    sim: SimChair = sim_factory(auth_secret=SECRET)
    ros = LinkRos("127.0.0.1", sim.port, thread_name="pmk-test-auth")
    t = int(time.time())
    ros.authenticate(_mac(SECRET, "xyz", t, t + 600), "127.0.0.1", "127.0.0.1", "xyz", t, "user", t + 600)
    got = threading.Event()
    try:
        ros.connect()
        assert ros.settled.wait(10), "the websocket did not open"
        roslibpy.Topic(ros, "/odom", "nav_msgs/Odometry").subscribe(lambda _m: got.set())
        assert got.wait(10), "an authenticated roslibpy client got no odometry"
    finally:
        ros.shutdown(2.0)


def test_the_link_authenticates_with_its_secret_file(sim_factory: Any, tmp_path: Path) -> None:  # noqa: F811
    sim: SimChair = sim_factory(auth_secret=SECRET)
    good, bad = tmp_path / "good", tmp_path / "bad"
    good.write_text(SECRET + "\n")
    bad.write_text("not this chair's secret\n")
    link = ChairLink("127.0.0.1", sim.port, auth=BridgeAuth(good))
    try:
        link.connect(timeout=10)
        link.start_streams()
        assert wait_until(lambda: link.latest_odom() is not None, 10), "the authenticated link got no odometry"
    finally:
        link.close()
    other = ChairLink("127.0.0.1", sim.port, auth=BridgeAuth(bad))
    with pytest.raises(BridgeAuthError) as info:
        other.connect(timeout=10)
    other.close()
    assert info.value.refused and info.value.secret_file == bad
    missing = ChairLink("127.0.0.1", sim.port, auth=BridgeAuth(tmp_path / "missing"))
    with pytest.raises(BridgeAuthError) as info:
        missing.connect(timeout=10)
    missing.close()
    assert not info.value.refused
