"""The simulator's SFTP endpoint with real clients (asyncssh, paramiko), then a hot reload of the upload."""

from __future__ import annotations

import asyncio
import base64
import hashlib

import asyncssh
import paramiko
import pytest
import roslibpy

from pmk_nb.grid import OccupancyGrid
from tests.fixtures_sim import paramiko_sftp, room_grid, wait_until, write_test_map


def test_fingerprint_matches_host_key(sim_factory):
    sim = sim_factory(sftp_port=0)
    blob = base64.b64decode(sim.sftp_host_key.split()[1])
    expected = "SHA256:" + base64.b64encode(hashlib.sha256(blob).digest()).decode().rstrip("=")
    assert sim.sftp_host_key_fingerprint == expected
    assert sim.sftp_port and sim.sftp_port != sim.port


def test_paramiko_upload_then_change_map(sim_factory, ros_factory, tmp_path):
    sim = sim_factory(sftp_port=0, grid=room_grid(6.0, 4.0), start_pose=(1.0, 2.0, 0.0))
    local = write_test_map(room_grid(6.0, 4.0, wall_x=2.5), tmp_path / "local", "ward")
    client, sftp = paramiko_sftp(sim, password=sim.sftp_password)
    try:
        assert sftp.normalize(".") == "/home/pmk"
        assert "ALMA_MAPS" in sftp.listdir(".")
        sftp.put(str(local.with_suffix(".pgm")), "ALMA_MAPS/ward.pgm")
        sftp.put(str(local), "ALMA_MAPS/ward.yaml")
        assert sorted(sftp.listdir("/home/pmk/ALMA_MAPS")) == ["ward.pgm", "ward.yaml"]
    finally:
        client.close()
    assert (sim.maps_dir / "ward.yaml").read_bytes() == local.read_bytes()

    ros = ros_factory(sim)
    scans: list[dict] = []
    roslibpy.Topic(ros, "/scan", "sensor_msgs/LaserScan").subscribe(scans.append)
    assert wait_until(lambda: bool(scans), 3.0)
    assert scans[-1]["ranges"][360] > 4.0
    reply = roslibpy.Service(ros, "/change_map", "nav_msgs/LoadMap").call(
        roslibpy.ServiceRequest({"map_url": "/home/pmk/ALMA_MAPS/ward.yaml"}), timeout=10
    )
    assert reply["result"] == 0
    maps: list[dict] = []
    roslibpy.Topic(ros, "/map", "nav_msgs/OccupancyGrid").subscribe(maps.append)
    assert wait_until(lambda: bool(maps), 3.0)
    assert OccupancyGrid.from_ros_msg(maps[-1]).data[40, 50] == 100  # the wall at x = 2.5 m
    scans.clear()
    assert wait_until(lambda: len(scans) >= 2, 3.0)
    assert scans[-1]["ranges"][360] == pytest.approx(1.5, abs=0.06)


def test_wrong_password_refused(sim_factory):
    sim = sim_factory(sftp_port=0)
    with pytest.raises(paramiko.AuthenticationException):
        paramiko_sftp(sim, password="not-the-password")


def test_paths_outside_maps_stay_in_scratch(sim_factory, tmp_path):
    sim = sim_factory(sftp_port=0)
    client, sftp = paramiko_sftp(sim, password=sim.sftp_password)
    try:
        with pytest.raises(IOError):
            sftp.listdir("/etc")
        with sftp.open("/home/pmk/notes.txt", "w") as fh:
            fh.write("x")
        sftp.put(__file__, "~/ALMA_MAPS/copy.py")  # "~" as the thesis app sent it
    finally:
        client.close()
    assert not (sim.maps_dir / "notes.txt").exists()
    assert (sim.maps_dir / "copy.py").exists()


def test_asyncssh_client_with_public_key(sim_factory, tmp_path):
    user_key = asyncssh.generate_private_key("ssh-ed25519")
    sim = sim_factory(sftp_port=0, sftp_authorized_key=user_key.export_public_key().decode())
    local = write_test_map(room_grid(3.0, 3.0), tmp_path, "tiny")

    async def upload() -> list[str]:
        known = asyncssh.import_known_hosts(f"[127.0.0.1]:{sim.sftp_port} {sim.sftp_host_key}\n")
        async with (
            asyncssh.connect(
                "127.0.0.1",
                sim.sftp_port,
                username=sim.config.sftp_user,
                client_keys=[user_key],
                known_hosts=known,
                password=None,
            ) as conn,
            conn.start_sftp_client() as sftp,
        ):
            await sftp.put([str(local), str(local.with_suffix(".pgm"))], "ALMA_MAPS/")
            return sorted(await sftp.listdir("ALMA_MAPS"))

    names = asyncio.run(asyncio.wait_for(upload(), 20))
    assert "tiny.yaml" in names and "tiny.pgm" in names
    assert sim.load_map("/home/pmk/ALMA_MAPS/tiny.yaml") == 0
    assert sim.grid.width == 60


def test_host_key_survives_restart(sim_factory):
    sim = sim_factory(sftp_port=0)
    before = sim.sftp_host_key_fingerprint
    sim.stop()
    sim.start()
    assert sim.sftp_host_key_fingerprint == before
