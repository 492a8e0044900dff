"""`pmk sim` as a user runs it: prints where it serves, answers, and stops cleanly on SIGTERM."""

from __future__ import annotations

import json
import re
import signal
import subprocess
import sys
import time

from websockets.sync.client import connect

from tests.fixtures_sim import room_grid, write_test_map


def start_cli(*args: str) -> tuple[subprocess.Popen[str], list[str]]:
    proc = subprocess.Popen(
        [sys.executable, "-m", "pmk_nb.cli", "sim", "--port", "0", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    lines: list[str] = []
    deadline = time.monotonic() + 30
    assert proc.stdout is not None
    while time.monotonic() < deadline:
        line = proc.stdout.readline()
        if not line:
            break
        lines.append(line.rstrip())
        if line.startswith("pmk sim: ready"):
            return proc, lines
    proc.kill()
    raise AssertionError("no ready line:\n" + "\n".join(lines))


def test_cli_serves_and_stops_on_sigterm(tmp_path):
    yaml = write_test_map(room_grid(5.0, 4.0), tmp_path, "room")
    proc, lines = start_cli("--sftp-port", "0", "--map", str(yaml), "--maps-dir", str(tmp_path), "--flavour", "ros2")
    try:
        text = "\n".join(lines)
        url = re.search(r"ws://127\.0\.0\.1:\d+", text)
        assert url, text
        assert "/odom [nav_msgs/msg/Odometry]" in text
        assert "/map_server/load_map [nav2_msgs/srv/LoadMap]" in text
        assert re.search(r"sftp: pmk@127\.0\.0\.1 port \d+ password \S+", text)
        assert "SHA256:" in text
        assert "room.yaml" in text
        with connect(url.group(0), open_timeout=5) as ws:
            ws.send(
                json.dumps(
                    {"op": "call_service", "id": "1", "service": "/rosapi/topic_type", "args": {"topic": "/scan"}}
                )
            )
            assert json.loads(ws.recv(timeout=5))["values"]["type"] == "sensor_msgs/msg/LaserScan"
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=10) == 0
        rest = proc.stdout.read() if proc.stdout else ""
        assert "pmk sim: stopped" in rest
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_cli_sigint_and_sample_map():
    proc, lines = start_cli("--no-sftp")
    try:
        assert any("sample" in line and "clinic_floor.gml" in line for line in lines), lines
        assert not any(line.strip().startswith("sftp:") for line in lines)
        proc.send_signal(signal.SIGINT)
        assert proc.wait(timeout=10) == 0
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_cli_bad_map_is_a_clear_error(tmp_path):
    proc = subprocess.run(
        [sys.executable, "-m", "pmk_nb.cli", "sim", "--port", "0", "--no-sftp", "--map", str(tmp_path / "no.yaml")],
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert proc.returncode == 2
    assert "no.yaml" in proc.stderr
