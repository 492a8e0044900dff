"""Real-stack tier, fault 9: plain ``roslibpy.Ros`` and the chair link in one process, either order.

Autobahn binds one framework per process ("Explicitly using 'twisted' already"). A notebook user who
made a plain ``roslibpy.Ros`` first (Twisted, roslibpy's default) and then a chair link, or the other
way round, must get both working. Each case runs in a fresh interpreter against rosbridge-server-rs
bridging the project's sim node.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests import fixtures_ros2
from tests.fixtures_ros2 import RealChair

ros2_stack, real_chair = fixtures_ros2.ros2_stack, fixtures_ros2.real_chair
ROOT = Path(__file__).resolve().parents[2]

PRELUDE = """
import json, sys, threading, time
port = int(sys.argv[1])

def wait(cond, timeout=15.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if cond():
            return True
        time.sleep(0.05)
    return False

def plain_odom(ros):
    import roslibpy
    got = []
    topic = roslibpy.Topic(ros, "/odom", "nav_msgs/msg/Odometry")
    topic.subscribe(got.append)
    ok = wait(lambda: bool(got))
    topic.unsubscribe()
    return ok

def link_round(port):
    from pmk_nb.chair.link.client import ChairLink
    link = ChairLink("127.0.0.1", port)
    link.connect(10)
    link.start_streams()
    ok = wait(lambda: link.latest_odom() is not None and link.latest_scan() is not None)
    link.close()
    return ok and not link.is_connected
"""

CASES = {
    "plain roslibpy first": """
import roslibpy
ros = roslibpy.Ros("127.0.0.1", port)   # roslibpy's default: Twisted
ros.run(10)
first = plain_odom(ros)
import pmk_nb.chair.link                 # after Twisted is bound
links = [link_round(port), link_round(port)]   # close and open again on the shared reactor
after = plain_odom(ros)                   # the user's client outlived the links
print(json.dumps({"factory": type(ros.factory).__name__, "plain": [first, after], "links": links}))
""",
    "chair link first": """
import roslibpy
import pmk_nb.chair.link
links = [link_round(port)]
ros = roslibpy.Ros("127.0.0.1", port)   # no transport=: what roslibpy picks now
ros.run(10)
first = plain_odom(ros)
links.append(link_round(port))
after = plain_odom(ros)
print(json.dumps({"factory": type(ros.factory).__name__, "plain": [first, after], "links": links}))
""",
    "another Autobahn/Twisted library first": """
import autobahn.twisted.websocket   # binds txaio to Twisted without roslibpy
import roslibpy
links = [link_round(port), link_round(port)]
ros = roslibpy.Ros("127.0.0.1", port)
ros.run(10)
print(json.dumps({"factory": type(ros.factory).__name__, "plain": [plain_odom(ros)], "links": links}))
""",
}
FACTORY = {
    "plain roslibpy first": "AutobahnRosBridgeClientFactory",
    "chair link first": "AsyncioRosBridgeClientFactory",
    "another Autobahn/Twisted library first": "AutobahnRosBridgeClientFactory",
}


@pytest.fixture
def chair(real_chair: RealChair) -> RealChair:
    real_chair.start_bridge()
    real_chair.start_sim_node()
    return real_chair


@pytest.mark.parametrize("case", list(CASES))
def test_plain_roslibpy_and_the_link_work_in_either_order(chair: RealChair, case: str) -> None:
    env = {k: v for k, v in os.environ.items() if k != "ROSLIBPY_TRANSPORT"}  # the user's default
    out = subprocess.run(
        [sys.executable, "-c", PRELUDE + CASES[case], str(chair.port)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 0, out.stderr[-3000:]
    result = json.loads(out.stdout.strip().splitlines()[-1])
    assert result["factory"] == FACTORY[case]
    assert all(result["plain"]), (result, out.stderr[-2000:])  # the plain client got odometry every time
    assert all(result["links"]), (result, out.stderr[-2000:])  # every link got odometry + scans and closed
