"""rosbridge v2 conformance of the simulator against a second real client: roslibjs (npm ``roslib``) in Node.

roslibpy and the dashboard were written against the simulator, so they can share its blind spots;
roslibjs is the reference JavaScript client and sends exactly what a browser UI would. The Node
script ``tests/js/roslib_client.mjs`` connects, subscribes /odom, /scan and latched /map (also
png-compressed, /odom with cbor which must fall back to JSON, and the relative name ``odom``),
publishes /cmd_vel, calls rosapi, the reload service with bad paths, an unknown service, a
service another roslibjs socket provides, and the ``ROSLIB.Ros`` helpers, then prints one JSON
line. One run per ROS version (module scope) feeds all the tests below.

Node >= 20 and npm are required; the npm packages are installed from ``tests/js/package-lock.json``
(``npm ci``) on first use when ``tests/js/node_modules`` is missing or stale.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import shutil
import subprocess
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.sim import SimChair, SimConfig
from tests.fixtures_sim import wait_until

pytestmark = pytest.mark.slow  # every test waits on a Node process running roslibjs

JS_DIR = Path(__file__).parents[1] / "js"
SCRIPT = JS_DIR / "roslib_client.mjs"
WINDOW_S = 1.2  # how long the script listens to /odom and /scan
NPM_CI_TIMEOUT_S = 240.0


def _locked_versions() -> dict[str, str]:
    """Package folder (``node_modules/x``) -> version, as ``package-lock.json`` pins them."""
    lock = json.loads((JS_DIR / "package-lock.json").read_text(encoding="utf-8"))
    return {path: str(meta["version"]) for path, meta in lock["packages"].items() if path.startswith("node_modules/")}


def _locked_roslib_version() -> str:
    return _locked_versions()["node_modules/roslib"]


def _stale_packages() -> list[str]:
    """Locked packages missing from ``tests/js/node_modules`` or installed at another version."""
    stale = []
    for path, version in _locked_versions().items():
        try:
            got = json.loads((JS_DIR / path / "package.json").read_text(encoding="utf-8")).get("version")
        except (OSError, ValueError):
            got = None
        if got != version:
            stale.append(f"{path.removeprefix('node_modules/')} {got or 'missing'} (locked {version})")
    return stale


@pytest.fixture(scope="session")
def node_client() -> Path:
    """The Node script, with its npm dependencies installed (``npm ci`` once, under a lock)."""
    node, npm = shutil.which("node"), shutil.which("npm")
    if node is None or npm is None:
        pytest.fail("roslibjs tests need Node.js >= 20 and npm on PATH (install nodejs + npm, then `make test`)")
    major = subprocess.run([node, "--version"], capture_output=True, text=True, timeout=30).stdout.strip()
    if not major.startswith("v") or int(major[1:].split(".")[0]) < 20:
        pytest.fail(f"roslibjs 2.x needs Node.js >= 20, found {major or 'unknown'} at {node}")
    digest = hashlib.sha1(str(JS_DIR).encode()).hexdigest()[:12]
    lock_path = Path(tempfile.gettempdir()) / f"pmk-npm-ci-{digest}.lock"
    with open(lock_path, "w") as lock:  # parallel pytest runs must not run npm ci into one folder at once
        fcntl.flock(lock, fcntl.LOCK_EX)
        if _stale_packages():
            try:
                done = subprocess.run(
                    [npm, "ci", "--no-audit", "--no-fund"],
                    cwd=JS_DIR,
                    capture_output=True,
                    text=True,
                    timeout=NPM_CI_TIMEOUT_S,
                )
            except subprocess.TimeoutExpired:
                pytest.fail(
                    f"`npm ci` in {JS_DIR} took more than {NPM_CI_TIMEOUT_S:.0f} s (is the npm registry reachable?)"
                )
            if done.returncode != 0:
                pytest.fail(f"`npm ci` in {JS_DIR} failed (exit {done.returncode}):\n{done.stderr[-2000:]}")
        stale = _stale_packages()
        if stale:
            pytest.fail(f"npm packages in {JS_DIR / 'node_modules'} do not match package-lock.json: {stale}")
    return SCRIPT


def run_client(script: Path, sim: SimChair, missing_map: Path) -> dict[str, Any]:
    cmd = [
        shutil.which("node") or "node",
        str(script),
        "--url",
        sim.url,
        "--flavour",
        sim.config.ros,
        "--seconds",
        str(WINDOW_S),
        "--missing-map",
        str(missing_map),
        "--timeout",
        "5",
    ]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    lines = done.stdout.strip().splitlines()
    assert lines, f"roslib_client.mjs printed nothing (exit {done.returncode}):\n{done.stderr[-2000:]}"
    result = json.loads(lines[-1])
    assert done.returncode == 0 and "fatal" not in result, f"roslib_client.mjs failed: {result.get('fatal')}"
    return result


@pytest.fixture(scope="module", params=["ros1", "ros2"])
def run(request: pytest.FixtureRequest, node_client: Path, tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict]:
    """One roslibjs session against a fresh chair of each ROS version; the result plus the chair's view."""
    ros = request.param
    tmp = tmp_path_factory.mktemp(f"roslibjs-{ros}")
    sim = SimChair(SimConfig(ros=ros, maps_dir=tmp / "ALMA_MAPS")).start()
    try:
        start = sim.pose
        result = run_client(node_client, sim, tmp / "ALMA_MAPS" / "no_such_map.yaml")  # in its folder: missing
        yield {
            "ros": ros,
            "result": result,
            "start_pose": start,
            "end_pose": sim.pose,
            "sim_odom_rate": sim.config.odom_rate,
            "sim_rays": sim.laser.rays,
            "grid": sim.grid,
            "clients_left": 0 if wait_until(lambda: sim.client_count == 0, 3.0) else sim.client_count,
        }
    finally:
        sim.stop()


def _stamp_keys(ros: str) -> list[str]:
    return ["nsecs", "secs"] if ros == "ros1" else ["nanosec", "sec"]


def test_roslib_version_and_connection(run: dict) -> None:
    res = run["result"]
    assert res["connected"] is True
    assert res["roslib"] == _locked_roslib_version()
    assert res["log"]["errors"] == [], res["log"]["errors"]
    assert res["log"]["closed"] is True  # the client's close reached the socket cleanly


def test_odom_stream(run: dict) -> None:
    odom = run["result"]["odom"]
    # wide bands: this checks the stream is the configured one, not timing (2 shared cores under load)
    assert odom["count"] >= 0.3 * run["sim_odom_rate"] * WINDOW_S, odom
    assert 0.25 * run["sim_odom_rate"] <= odom["rate"] <= 1.6 * run["sim_odom_rate"], odom  # 19.6 Hz seen
    assert odom["stampKeys"] == _stamp_keys(run["ros"])
    assert ("seq" in odom["headerKeys"]) == (run["ros"] == "ros1")  # Header.seq is ROS 1 only
    assert (odom["frameId"], odom["childFrameId"]) == ("odom", "base_link")
    assert odom["extraAfterUnsubscribe"] == 0  # unsubscribe by roslibjs' id stops the stream


def test_scan_stream(run: dict) -> None:
    scan = run["result"]["scan"]
    assert scan["count"] >= 5, scan
    assert scan["ranges"] == run["sim_rays"] == 720
    assert scan["stampKeys"] == _stamp_keys(run["ros"])
    span = scan["angleMax"] - scan["angleMin"]
    assert span == pytest.approx(scan["angleIncrement"] * (scan["ranges"] - 1), rel=1e-9)
    assert span == pytest.approx(4.712, abs=0.02)  # 270 degrees


def test_latched_map_plain_and_png(run: dict) -> None:
    grid = run["grid"]
    for key in ("map", "mapPng"):
        m = run["result"][key]
        assert m["count"] == 1, (key, m)  # latched: exactly the one stored message on subscribe
        assert (m["width"], m["height"]) == (grid.width, grid.height), key
        assert m["resolution"] == pytest.approx(grid.resolution)
        assert m["dataLength"] == grid.width * grid.height
        assert m["stampKeys"] == _stamp_keys(run["ros"])
        assert m["frameId"] == "map"


def test_cbor_subscription_falls_back_to_json(run: dict) -> None:
    assert run["result"]["odomCbor"]["count"] > 0
    assert run["result"]["secondLog"]["errors"] == []


def test_cmd_vel_from_roslibjs_drives_the_chair(run: dict) -> None:
    res = run["result"]
    assert res["cmdVel"]["published"] >= 5
    assert res["odom"]["maxVx"] > 0.05  # the chair's own odometry reports the commanded speed
    (x0, y0, _), (x1, y1, _) = run["start_pose"], run["end_pose"]
    assert ((x1 - x0) ** 2 + (y1 - y0) ** 2) ** 0.5 > 0.05


def test_rosapi_topics_by_absolute_name(run: dict) -> None:
    call = run["result"]["calls"]["rosapiTopics"]
    assert call["ok"], call
    topics = dict(zip(call["value"]["topics"], call["value"]["types"], strict=True))
    odom_type = "nav_msgs/Odometry" if run["ros"] == "ros1" else "nav_msgs/msg/Odometry"
    assert topics["/odom"] == odom_type
    assert {"/scan", "/map", "/cmd_vel"} <= topics.keys()


def test_reload_with_missing_and_empty_path_fails_with_code(run: dict) -> None:
    calls = run["result"]["calls"]
    missing, empty = calls["reload"], calls["reloadEmpty"]
    assert missing["ok"] and empty["ok"], (missing, empty)  # the service ran; the failure is in the result
    if run["ros"] == "ros1":  # Noetic map_server: success or RESULT_UNDEFINED_FAILURE only
        assert missing["service"] == "/change_map"
        assert missing["value"]["result"] == empty["value"]["result"] == 255
    else:  # Nav2: yaml missing -> INVALID_MAP_METADATA, empty url -> MAP_DOES_NOT_EXIST
        assert missing["service"] == "/map_server/load_map"
        assert (missing["value"]["result"], empty["value"]["result"]) == (3, 1)
    assert missing["value"]["map"]["info"]["width"] == 0  # no map in a failed reply


def test_unknown_service_calls_error_callback(run: dict) -> None:
    res = run["result"]
    call = res["calls"]["unknown"]
    assert call["ok"] is False and not call.get("timedOut"), call
    assert "/no_such_service" in call["error"]
    errors = [s for s in res["log"]["status"] if s["level"] == "error" and "/no_such_service" in s["msg"]]
    assert errors and errors[0]["id"].startswith("call_service:/no_such_service:")


def test_service_provided_by_a_roslibjs_client(run: dict) -> None:
    """advertise_service / call_service / service_response routed between two roslibjs sockets."""
    p = run["result"]["provided"]
    assert p["seen"] == [{"data": True}, {"data": False}]
    assert p["on"] == {"ok": True, "value": {"success": True, "message": "flag on"}, "ms": p["on"]["ms"]}
    assert p["off"]["ok"] is False and "refused by provider" in p["off"]["error"]
    assert p["gone"]["ok"] is False and not p["gone"].get("timedOut")  # unadvertised: fails, no hang
    assert "does not exist" in p["gone"]["error"]


def test_ros_helpers_with_relative_rosapi_names(run: dict) -> None:
    calls = run["result"]["calls"]
    for key in ("getTopics", "getServices", "topicType", "topicTypeUnknown", "topicsForType", "serviceType"):
        assert calls[key]["ok"], (key, calls[key])
    odom_type = "nav_msgs/Odometry" if run["ros"] == "ros1" else "nav_msgs/msg/Odometry"
    assert "/odom" in calls["getTopics"]["value"]["topics"]
    reload = calls["reload"]["service"]
    assert {"/rosapi/topics", reload} <= set(calls["getServices"]["value"])
    assert calls["topicType"]["value"] == odom_type
    assert calls["topicTypeUnknown"]["value"] == ""
    assert "/odom" in calls["topicsForType"]["value"]
    assert calls["serviceType"]["value"].endswith("LoadMap")


def test_relative_topic_subscription_resolves(run: dict) -> None:
    res = run["result"]
    assert res["odomRelative"]["count"] > 0
    assert "odom" not in res["calls"]["rosapiTopics"]["value"]["topics"]  # no phantom topic


def test_client_left_no_session_behind(run: dict) -> None:
    assert run["clients_left"] == 0
