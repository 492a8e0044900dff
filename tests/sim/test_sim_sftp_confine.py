"""The simulator's SFTP endpoint stays inside its folders, even with symlinks (real paramiko/asyncssh clients).

Every path a client names is checked by its real path against the sim's two roots (the maps folder
and the private scratch home), and the endpoint refuses to create symlinks at all.
"""

from __future__ import annotations

import asyncio
import os

import asyncssh
import pytest

from tests.fixtures_sim import paramiko_sftp

SECRET = b"host file outside the simulator\n"


def test_symlink_creation_refused_paramiko(sim_factory):
    sim = sim_factory(sftp_port=0)
    client, sftp = paramiko_sftp(sim, password=sim.sftp_password)
    try:
        with pytest.raises(IOError):
            sftp.symlink("/home/pmk/ALMA_MAPS", "/home/pmk/ALMA_MAPS/loop")
        with pytest.raises(IOError):
            sftp.symlink("notes.txt", "/home/pmk/link.txt")
    finally:
        client.close()
    assert not os.path.lexists(sim.maps_dir / "loop")
    assert sorted(os.listdir(sim.maps_dir)) == []


def test_symlink_creation_refused_asyncssh(sim_factory):
    sim = sim_factory(sftp_port=0)

    async def try_link() -> type[BaseException] | None:
        known = asyncssh.import_known_hosts(f"[127.0.0.1]:{sim.sftp_port} {sim.sftp_host_key}\n")
        async with (
            asyncssh.connect(
                "127.0.0.1", sim.sftp_port, username=sim.config.sftp_user, password=sim.sftp_password, known_hosts=known
            ) as conn,
            conn.start_sftp_client() as sftp,
        ):
            try:
                await sftp.symlink("/home/pmk/ALMA_MAPS", "ALMA_MAPS/loop")
            except asyncssh.SFTPError as err:
                return type(err)
            return None

    refused = asyncio.run(asyncio.wait_for(try_link(), 20))
    assert refused is not None and issubclass(refused, asyncssh.SFTPError)
    assert not os.path.lexists(sim.maps_dir / "loop")


def test_two_step_relative_link_escape_fails(sim_factory, tmp_path):
    """The issue's escape: a link to the maps folder, then a relative link through it, reached maps_dir/.."""
    sim = sim_factory(sftp_port=0)
    outside = sim.maps_dir.parent / "secret.txt"
    outside.write_bytes(SECRET)
    client, sftp = paramiko_sftp(sim, password=sim.sftp_password)
    try:
        for target, link in (("/home/pmk/ALMA_MAPS", "ALMA_MAPS/m"), ("../secret.txt", "ALMA_MAPS/m/e")):
            try:
                sftp.symlink(target, link)
            except OSError:
                pass  # refused: that is the fix; the reads and writes below must fail either way
        with pytest.raises(IOError), sftp.open("ALMA_MAPS/e", "r") as fh:
            fh.read()
        with sftp.open("ALMA_MAPS/e", "w") as fh:  # no link there any more: a plain new file in the maps folder
            fh.write("overwritten")
    finally:
        client.close()
    assert outside.read_bytes() == SECRET
    assert not (sim.maps_dir / "e").is_symlink() and (sim.maps_dir / "e").read_bytes() == b"overwritten"


def test_planted_file_link_pointing_outside_refused(sim_factory, tmp_path):
    sim = sim_factory(sftp_port=0)
    outside = tmp_path / "outside.txt"
    outside.write_bytes(SECRET)
    os.symlink(outside, sim.maps_dir / "out.txt")
    inside = sim.maps_dir / "real.txt"
    inside.write_bytes(b"in the maps folder\n")
    os.symlink(inside, sim.maps_dir / "alias.txt")  # a link that stays inside is fine
    client, sftp = paramiko_sftp(sim, password=sim.sftp_password)
    try:
        with pytest.raises(IOError), sftp.open("ALMA_MAPS/out.txt", "r") as fh:
            fh.read()
        with pytest.raises(IOError), sftp.open("/home/pmk/ALMA_MAPS/out.txt", "w") as fh:
            fh.write("overwritten")
        with pytest.raises(IOError):
            sftp.stat("ALMA_MAPS/out.txt")
        with sftp.open("ALMA_MAPS/alias.txt", "r") as fh:
            assert fh.read() == b"in the maps folder\n"
    finally:
        client.close()
    assert outside.read_bytes() == SECRET


def test_planted_folder_link_pointing_outside_refused(sim_factory, tmp_path):
    sim = sim_factory(sftp_port=0)
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    (outside / "keep.txt").write_bytes(SECRET)
    os.symlink(outside, sim.maps_dir / "sub", target_is_directory=True)
    client, sftp = paramiko_sftp(sim, password=sim.sftp_password)
    try:
        with pytest.raises(IOError):
            sftp.listdir("ALMA_MAPS/sub")
        with pytest.raises(IOError), sftp.open("ALMA_MAPS/sub/keep.txt", "r") as fh:
            fh.read()
        with pytest.raises(IOError), sftp.open("ALMA_MAPS/sub/new.txt", "w") as fh:  # new file: parent checked
            fh.write("x")
        with pytest.raises(IOError):
            sftp.mkdir("ALMA_MAPS/sub/dir")
        with pytest.raises(IOError):
            sftp.normalize("ALMA_MAPS/sub")
    finally:
        client.close()
    assert sorted(p.name for p in outside.iterdir()) == ["keep.txt"]
    assert (outside / "keep.txt").read_bytes() == SECRET


def test_the_maps_folder_cannot_be_renamed_away(sim_factory):
    """Issue 38: ``rename("ALMA_MAPS", "../moved")`` moved the maps folder into the scratch home."""
    sim = sim_factory(sftp_port=0)
    maps = sim.maps_dir
    (maps / "kept.yaml").write_bytes(b"image: kept.pgm\n")
    client, sftp = paramiko_sftp(sim, password=sim.sftp_password)
    try:
        for old, new in (("ALMA_MAPS", "../moved"), ("/home/pmk/ALMA_MAPS", "moved"), ("~/ALMA_MAPS", "x/..")):
            with pytest.raises(IOError):
                sftp.rename(old, new)
            with pytest.raises(IOError):
                sftp.posix_rename(old, new)
        with pytest.raises(IOError):
            sftp.rename("/", "ALMA_MAPS/home")  # the scratch home is a root too
        sftp.mkdir("spare")
        with pytest.raises(IOError):
            sftp.rename("spare", "ALMA_MAPS/sub/../..")
        sftp.rename("ALMA_MAPS/kept.yaml", "ALMA_MAPS/renamed.yaml")  # inside the folder: as before
        sftp.rename("ALMA_MAPS/renamed.yaml", "parked.yaml")  # out to the home and back: both sides confined
        sftp.posix_rename("parked.yaml", "ALMA_MAPS/kept.yaml")
    finally:
        client.close()
    assert maps.is_dir() and sorted(os.listdir(maps)) == ["kept.yaml"]
    assert (maps / "kept.yaml").read_bytes() == b"image: kept.pgm\n"


def test_an_empty_maps_folder_is_neither_replaced_nor_removed(sim_factory):
    sim = sim_factory(sftp_port=0)
    maps = sim.maps_dir
    client, sftp = paramiko_sftp(sim, password=sim.sftp_password)
    try:
        sftp.mkdir("other")
        with sftp.open("other/marker.txt", "w") as fh:
            fh.write("not the maps")
        with pytest.raises(IOError):
            sftp.posix_rename("other", "ALMA_MAPS")  # os.replace would swap an empty folder for it
        with pytest.raises(IOError):
            sftp.rmdir("ALMA_MAPS")
        with pytest.raises(IOError):
            sftp.rmdir("/home/pmk/ALMA_MAPS/")
    finally:
        client.close()
    assert maps.is_dir() and os.listdir(maps) == []
