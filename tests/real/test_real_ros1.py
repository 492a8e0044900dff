"""Real-stack tier, ROS 1: the PMK map server as a rospy node against a real rosmaster (issue 9).

Debian's ROS 1 (python3-rospy, python3-rosmaster, python3-nav-msgs; `make system-deps`) runs with the
system Python, so the rospy client of each test runs there too, as a child process answering JSON.
Everything listens on 127.0.0.1 (ROS_IP) on a free port; a missing ROS 1 install FAILS, never skips.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from pmk_nb.robot import ros1_mapserver
from pmk_nb.rosmap import read_map
from pmk_nb.wire import grid_sha256
from tests.fixtures_ros2 import free_port
from tests.fixtures_sim import room_grid, write_test_map

ROOT = Path(__file__).resolve().parents[2]
SRV_DIR = ROOT / "ros" / "interfaces" / "map_server_pmk" / "srv"


class Ros1:
    """A rosmaster on a free loopback port and the environment its nodes and clients need."""

    def __init__(self, tmp: Path) -> None:
        self.port = free_port()
        self.tmp = tmp
        self.env = {
            **os.environ,
            "ROS_MASTER_URI": f"http://127.0.0.1:{self.port}",
            "ROS_IP": "127.0.0.1",
            "ROS_HOME": str(tmp / "ros_home"),
            "PYTHONPATH": str(ROOT),
        }
        self.procs: list[subprocess.Popen[bytes]] = []

    def spawn(self, cmd: list[str], log: str) -> subprocess.Popen[bytes]:
        out = (self.tmp / log).open("wb")
        proc = subprocess.Popen(cmd, env=self.env, stdout=out, stderr=subprocess.STDOUT, cwd=self.tmp)
        self.procs.append(proc)
        return proc

    def wait_line(self, log: str, text: str, timeout: float = 30) -> None:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if text in (self.tmp / log).read_text(errors="replace"):
                return
            time.sleep(0.1)
        pytest.fail(f"{text!r} not in {log} within {timeout} s:\n{(self.tmp / log).read_text(errors='replace')}")

    def client(self, code: str, timeout: float = 60) -> dict:
        """Run rospy client code (it prints one JSON line last) under the system Python."""
        out = subprocess.run(
            [ros1_mapserver.SYSTEM_PYTHON, "-c", CLIENT_PRELUDE + code],
            env=self.env,
            capture_output=True,
            text=True,
            timeout=timeout,
        )
        assert out.returncode == 0, out.stderr[-3000:]
        return json.loads(out.stdout.strip().splitlines()[-1])

    def stop(self) -> None:
        for proc in reversed(self.procs):
            if proc.poll() is None:
                proc.terminate()
                try:
                    proc.wait(10)
                except subprocess.TimeoutExpired:
                    proc.kill()
                    proc.wait(5)


CLIENT_PRELUDE = """
import json, rospy
from nav_msgs.msg import OccupancyGrid
from nav_msgs.srv import LoadMap
from pmk_nb.robot.ros1_mapserver import generate_srv
rospy.init_node("pmk_test_client", anonymous=True, disable_signals=True)
MapUpdate, MapInfo = generate_srv("MapUpdate"), generate_srv("MapInfo")
def latched_map():  # a fresh subscriber: only a latched /map reaches it
    m = rospy.wait_for_message("/map", OccupancyGrid, timeout=10)
    return [m.info.width, m.info.height, m.header.frame_id]
for name in ("/change_map", "/map_update", "/map_server/map_info"):
    rospy.wait_for_service(name, timeout=10)
"""


@pytest.fixture
def ros1(tmp_path: Path) -> Iterator[Ros1]:
    for tool in ("rosmaster", ros1_mapserver.SYSTEM_PYTHON):
        if shutil.which(tool) is None:
            pytest.fail(f"ROS 1 tier: {tool} missing; run `make system-deps` (python3-rospy, python3-rosmaster)")
    r = Ros1(tmp_path)
    try:
        r.spawn(["rosmaster", "--core", "-p", str(r.port)], "rosmaster.log")
        yield r
    finally:
        r.stop()


@pytest.fixture
def maps(tmp_path: Path) -> Path:
    folder = tmp_path / "ALMA_MAPS"
    folder.mkdir()
    write_test_map(room_grid(8.0, 6.0), folder, "room")  # 160 x 120
    write_test_map(room_grid(10.0, 4.0), folder, "long")  # 200 x 80
    return folder


def start_node(ros1: Ros1, maps: Path, *args: str) -> None:
    """``pmk robot map-server --ros1`` from the venv: the CLI hands over to the system Python."""
    cmd = [sys.executable, "-m", "pmk_nb.cli", "robot", "map-server", "--ros1", "--maps", str(maps), *args]
    ros1.spawn(cmd, "map_server.log")
    ros1.wait_line("map_server.log", ros1_mapserver.READY_LINE)


def test_change_map_reloads_and_republishes_the_latched_map(ros1: Ros1, maps: Path) -> None:
    start_node(ros1, maps, "--map", "room")
    out = ros1.client(
        """
first = latched_map()
ok = rospy.ServiceProxy("/change_map", LoadMap)("long.yaml")
after = latched_map()
outside = rospy.ServiceProxy("/change_map", LoadMap)("/etc/hostname")
missing = rospy.ServiceProxy("/change_map", LoadMap)("nope.yaml")
print(json.dumps({"first": first, "result": ok.result, "reply": [ok.map.info.width, ok.map.info.height],
                  "after": after, "outside": outside.result, "missing": missing.result, "still": latched_map()}))
"""
    )
    assert out["first"] == [160, 120, "map"]
    assert out["result"] == 0 and out["reply"] == [200, 80]
    assert out["after"] == [200, 80, "map"]
    # ROS 1's map_server answers every failure with RESULT_UNDEFINED_FAILURE; the map stays
    assert out["outside"] == 255 and out["missing"] == 255
    assert out["still"] == [200, 80, "map"]


def test_map_update_and_map_info_confirm_without_the_grid(ros1: Ros1, maps: Path) -> None:
    start_node(ros1, maps)  # no first map: map_info says so
    out = ros1.client(
        f"""
info0 = rospy.ServiceProxy("/map_server/map_info", MapInfo)()
done = rospy.ServiceProxy("/map_update", MapUpdate)("{maps / "long.yaml"}").done
refused = rospy.ServiceProxy("/map_update", MapUpdate)("../../etc/hostname").done
info = rospy.ServiceProxy("/map_server/map_info", MapInfo)()
print(json.dumps({{"loaded0": info0.loaded, "done": done, "refused": refused, "loaded": info.loaded,
                  "size": [info.info.width, info.info.height], "res": info.info.resolution,
                  "sha": info.sha256, "path": info.path, "map": latched_map(),
                  "md5": MapUpdate._md5sum, "type": MapUpdate._type}}))
"""
    )
    assert out["loaded0"] is False
    assert out["done"] is True and out["refused"] is False
    grid = read_map(maps / "long.yaml", reader="nav2_jazzy")
    assert out["loaded"] is True and out["size"] == [grid.width, grid.height] == [200, 80]
    assert out["res"] == pytest.approx(grid.resolution)
    assert out["sha"] == grid_sha256(grid) and out["path"] == str(maps / "long.yaml")
    assert out["map"] == [200, 80, "map"]
    assert out["type"] == "map_server_pmk/MapUpdate" and re.fullmatch(r"[0-9a-f]{32}", out["md5"])


def test_a_big_map_is_published_whole_and_the_reply_stays_small(ros1: Ros1, maps: Path) -> None:
    """2500 x 2500 (6.25 M cells, above the reply limit): /change_map answers 0 without the grid,
    the latched /map carries all of it (genpy writes the int8 cells as one NumPy buffer)."""
    write_test_map(room_grid(125.0, 125.0), maps, "big")
    start_node(ros1, maps, "--map", "room")
    out = ros1.client(
        """
import time
t0 = time.monotonic()
ok = rospy.ServiceProxy("/change_map", LoadMap)("big.yaml")
took = time.monotonic() - t0
m = rospy.wait_for_message("/map", OccupancyGrid, timeout=30)
info = rospy.ServiceProxy("/map_server/map_info", MapInfo)()
print(json.dumps({"result": ok.result, "reply_cells": len(ok.map.data), "took": took,
                  "map": [m.info.width, m.info.height, len(m.data), sum(1 for v in m.data[:2500] if v == 100)],
                  "sha": info.sha256}))
""",
        timeout=120,
    )
    grid = read_map(maps / "big.yaml", reader="nav2_jazzy")
    assert out["result"] == 0 and out["reply_cells"] == 0
    assert out["map"] == [2500, 2500, 2500 * 2500, 2500]  # row 0 (bottom) is the wall, all of it
    assert out["sha"] == grid_sha256(grid)


def test_service_texts_are_the_project_srv_files() -> None:
    """genpy generates from SRV_TEXTS: they must say what ros/interfaces says (comments aside)."""
    for name, text in ros1_mapserver.SRV_TEXTS.items():
        lines = [ln.split("#", 1)[0].strip() for ln in (SRV_DIR / f"{name}.srv").read_text().splitlines()]
        assert [ln for ln in lines if ln] == [ln for ln in text.splitlines() if ln], name


def test_the_node_runs_on_the_system_python_without_the_venv(tmp_path: Path) -> None:
    """Only stdlib, Debian's packages and the project's pure map store: importable by /usr/bin/python3."""
    code = "import pmk_nb.robot.ros1_mapserver, sys; print(sorted(k for k in sys.modules if k.startswith('pmk_nb')))"
    env = {"PATH": "/usr/bin:/bin", "PYTHONPATH": str(ROOT), "HOME": str(tmp_path)}
    cmd = [ros1_mapserver.SYSTEM_PYTHON, "-c", code]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert "pmk_nb.robot.mapstore" in out.stdout and "pmk_nb.ui" not in out.stdout
