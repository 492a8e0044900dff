"""`pmk sim` as a user runs it: prints where it serves, answers, stops cleanly on SIGTERM; SFTP auth options."""

from __future__ import annotations

import base64
import io
import json
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import asyncssh
import paramiko
import pytest
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


@pytest.mark.slow
def test_cli_serves_and_stops_on_sigterm(tmp_path):
    yaml = write_test_map(room_grid(5.0, 4.0), tmp_path, "room")
    proc, lines = start_cli("--sftp-port", "0", "--map", str(yaml), "--maps-dir", str(tmp_path), "--ros", "ros2")
    try:
        text = "\n".join(lines)
        url = re.search(r"ws://127\.0\.0\.1:\d+", text)
        assert url, text
        assert "/odom [nav_msgs/msg/Odometry]" in text
        assert "(ros2, bridge official)" in text  # the default bridge mode is said (issue 24)
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


@pytest.mark.slow
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


def _cli_paramiko(lines: list[str], **auth: object) -> paramiko.SSHClient:
    """Log in to the CLI sim's SFTP as printed (port, user, host key), with ``auth`` only."""
    text = "\n".join(lines)
    login = re.search(r"sftp: (\S+)@127\.0\.0\.1 port (\d+)", text)
    host_key = re.search(r"sftp host key: SHA256:\S+ \((ssh-ed25519) (\S+)", text)
    assert login and host_key, text
    client = paramiko.SSHClient()
    port = int(login.group(2))
    client.get_host_keys().add(
        f"[127.0.0.1]:{port}", host_key.group(1), paramiko.Ed25519Key(data=base64.b64decode(host_key.group(2)))
    )
    client.set_missing_host_key_policy(paramiko.RejectPolicy())
    client.connect(
        "127.0.0.1", port, username=login.group(1), allow_agent=False, look_for_keys=False, timeout=10, **auth
    )
    return client


def _user_key(tmp_path: Path) -> tuple[Path, Path, str]:
    """An ed25519 key pair on disk (private, public) and its SHA256 fingerprint."""
    key = asyncssh.generate_private_key("ssh-ed25519", comment="tester")
    private, public = tmp_path / "id_ed25519", tmp_path / "id_ed25519.pub"
    private.write_bytes(key.export_private_key("openssh"))
    public.write_bytes(b"# the chair's authorized_keys\n\n" + key.export_public_key("openssh"))
    return private, public, key.get_fingerprint("sha256")


def _stop(proc: subprocess.Popen[str]) -> None:
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(timeout=10) == 0


@pytest.mark.slow
def test_cli_authorized_key_and_password_both_log_in(tmp_path):
    private, public, fingerprint = _user_key(tmp_path)
    proc, lines = start_cli("--sftp-port", "0", "--sftp-authorized-key", str(public), "--sftp-password", "pw-123")
    try:
        assert any(f"sftp authorized keys: {fingerprint}" in line for line in lines), lines
        client = _cli_paramiko(lines, key_filename=str(private))
        try:
            sftp = client.open_sftp()
            sftp.putfo(io.BytesIO(b"x"), "ALMA_MAPS/by_key.txt")
            assert "by_key.txt" in sftp.listdir("ALMA_MAPS")
        finally:
            client.close()
        _cli_paramiko(lines, password="pw-123").close()
        with pytest.raises(paramiko.AuthenticationException):
            _cli_paramiko(lines, password="wrong")
        _stop(proc)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


@pytest.mark.slow
def test_cli_no_sftp_password_is_key_only(tmp_path):
    private, public, _ = _user_key(tmp_path)
    (tmp_path / "other").mkdir()
    other, _, _ = _user_key(tmp_path / "other")
    proc, lines = start_cli("--sftp-port", "0", "--sftp-authorized-key", str(public), "--no-sftp-password")
    try:
        assert any("key login only" in line for line in lines), lines
        assert not any("password" in line for line in lines if line.strip().startswith("sftp:")), lines
        _cli_paramiko(lines, key_filename=str(private)).close()
        with pytest.raises(paramiko.AuthenticationException):
            _cli_paramiko(lines, key_filename=str(other))  # a key that is not authorized
        with pytest.raises(paramiko.BadAuthenticationType) as refused:  # password auth is not even offered
            _cli_paramiko(lines, password="anything")
        assert refused.value.allowed_types == ["publickey"]
        _stop(proc)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


@pytest.mark.slow
@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["--no-sftp-password"], "--sftp-authorized-key"),
        (["--no-sftp-password", "--sftp-password", "x", "--sftp-authorized-key", "K"], "contradict"),
        (["--sftp-authorized-key", "MISSING"], "MISSING"),
        (["--sftp-authorized-key", "PRIVATE"], "not an OpenSSH public key"),
    ],
)
def test_cli_bad_sftp_auth_options_are_clear_errors(tmp_path, extra, needle):
    private, public, _ = _user_key(tmp_path)
    subst = {"K": str(public), "MISSING": str(tmp_path / "nope.pub"), "PRIVATE": str(private)}
    argv = [subst.get(a, a) for a in extra]
    proc = subprocess.run(
        [sys.executable, "-m", "pmk_nb.cli", "sim", "--port", "0", "--sftp-port", "0", *argv],
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert proc.returncode == 2, proc.stderr
    assert subst.get(needle, needle) in proc.stderr


@pytest.mark.parametrize("option", ["--ros", "--flavour"])
def test_cli_ros_version_option_and_its_old_name(option):
    from pmk_nb.cli import build_parser

    assert build_parser("sim").parse_args(["sim", option, "ros2"]).ros == "ros2"
    assert build_parser("sim").parse_args(["sim"]).ros == "ros1"


def test_cli_bridge_option_picks_the_rosbridge_to_imitate() -> None:
    from pmk_nb.cli import build_parser

    assert build_parser("sim").parse_args(["sim"]).bridge == "official"
    assert build_parser("sim").parse_args(["sim", "--bridge", "rs"]).bridge == "rs"
    with pytest.raises(SystemExit):
        build_parser("sim").parse_args(["sim", "--bridge", "ros1"])
