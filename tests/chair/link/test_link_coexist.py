"""Plain ``roslibpy.Ros(host, port)`` and the chair link in one process, against one simulator.

Autobahn binds one async framework (Twisted or asyncio) per process; importing the link must not
make user code with plain roslibpy fail, whichever is created first.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import threading
from pathlib import Path

import pytest
import roslibpy

import pmk_nb.chair.link as chair_link
from pmk_nb.sim import SimChair
from tests.fixtures_sim import wait_until

ROOT = Path(__file__).resolve().parents[3]


def _plain_ros(port: int) -> roslibpy.Ros:
    ros = roslibpy.Ros("127.0.0.1", port)  # no transport=: whatever roslibpy picks by default
    ros.run(5.0)
    return ros


def _plain_answers(ros: roslibpy.Ros) -> tuple[list[str], dict]:
    services = roslibpy.Service(ros, "/rosapi/services", "rosapi/Services").call(
        roslibpy.ServiceRequest({}), timeout=5.0
    )
    got: list[dict] = []
    odom = roslibpy.Topic(ros, "/odom", "nav_msgs/Odometry")
    odom.subscribe(got.append)
    assert wait_until(lambda: bool(got), 5.0)
    odom.unsubscribe()
    return list(services["services"]), got[0]


def _close_plain(ros: roslibpy.Ros) -> None:
    closed = threading.Event()
    ros.on("close", lambda *_: closed.set())
    ros.close()
    assert closed.wait(5.0)


@pytest.mark.parametrize("first", ["link", "plain"])
def test_plain_roslibpy_and_the_link_share_one_process(sim_chair: SimChair, first: str) -> None:
    link = chair_link.ChairLink("127.0.0.1", sim_chair.port)
    plain = None
    try:
        if first == "link":
            link.connect(timeout=10.0)
            plain = _plain_ros(sim_chair.port)
        else:
            plain = _plain_ros(sim_chair.port)
            link.connect(timeout=10.0)
        services, odom = _plain_answers(plain)
        assert "/rosapi/services" in services and "pose" in odom
        assert "/rosapi/services" in link.services()
        link.start_streams()
        assert wait_until(lambda: link.latest_odom() is not None, 5.0)
        assert wait_until(lambda: sim_chair.client_count == 2, 5.0)
        # two connections, two loops: the link does not run on the loop plain roslibpy uses
        assert link.ros is not None and link.ros.manager is not plain.factory.manager
    finally:
        link.close()
        if plain is not None:
            _close_plain(plain)
    assert not link.is_connected and not plain.is_connected
    assert wait_until(lambda: sim_chair.client_count == 0, 5.0)


def _run_child(code: str, port: int, **env: str) -> dict:
    child_env = {k: v for k, v in os.environ.items() if k != "ROSLIBPY_TRANSPORT"} | env
    out = subprocess.run(
        [sys.executable, "-c", code, str(port)],
        cwd=ROOT,
        env=child_env,
        capture_output=True,
        text=True,
        timeout=60,
        check=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


CHILD_TWISTED = """
import json, sys
import pmk_nb.chair.link as chair_link   # must not bind asyncio at import
from roslibpy.comm import select_factory
from pmk_nb.errors import ChairLinkError
factory = select_factory()               # twisted, as ROSLIBPY_TRANSPORT says: no txaio conflict
try:
    chair_link.ChairLink("127.0.0.1", int(sys.argv[1])).connect(timeout=5.0)
    result = "connected"
except ChairLinkError as err:
    result = type(err).__name__ + "|" + err.hint
print(json.dumps({"factory": factory.__name__, "link": result}))
"""


@pytest.mark.slow
def test_importing_the_link_keeps_a_process_that_chose_twisted_working(sim_chair: SimChair) -> None:
    out = _run_child(CHILD_TWISTED, sim_chair.port, ROSLIBPY_TRANSPORT="twisted")
    assert out["factory"] == "AutobahnRosBridgeClientFactory"
    # and the link joins it on roslibpy's Twisted transport (issue 9, fault 9), instead of failing
    assert out["link"] == "connected"


CHILD_DEFAULT = """
import json, sys
import roslibpy
import pmk_nb.chair.link as chair_link
port = int(sys.argv[1])
ros = roslibpy.Ros("127.0.0.1", port)
ros.run(5.0)
link = chair_link.ChairLink("127.0.0.1", port)
link.connect(timeout=5.0)
answer = roslibpy.Service(ros, "/rosapi/services", "rosapi/Services").call(roslibpy.ServiceRequest({}), timeout=5.0)
out = {"factory": type(ros.factory).__name__, "plain": len(answer["services"]), "link": len(link.services())}
print(json.dumps(out))
link.close()
ros.close()
"""


@pytest.mark.slow
def test_plain_ros_created_after_import_uses_the_shared_transport(sim_chair: SimChair) -> None:
    out = _run_child(CHILD_DEFAULT, sim_chair.port)
    assert out["factory"] == "AsyncioRosBridgeClientFactory"
    assert out["plain"] > 0 and out["plain"] == out["link"]
