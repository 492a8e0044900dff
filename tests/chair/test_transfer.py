"""SFTP upload against a real OpenSSH server (tests/fixtures_ssh.py)."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import threading
from pathlib import Path

import numpy as np
import pytest
import yaml

from pmk_nb.chair.profiles import ChairProfile
from pmk_nb.chair.transfer import check_ssh, upload, upload_map
from pmk_nb.errors import TransferError
from pmk_nb.grid import OccupancyGrid
from pmk_nb.progress import Progress
from pmk_nb.rosmap import MapFiles, write_map
from tests.fixtures_ssh import SshdServer, profile_for


def make_map(folder: Path, name: str, width: int = 40, height: int = 30, seed: int = 0) -> MapFiles:
    rng = np.random.default_rng(seed)
    data = rng.choice(np.array([-1, 0, 100], dtype=np.int8), size=(height, width))
    grid = OccupancyGrid(data=data, resolution=0.05, origin=(-1.0, -2.0, 0.0))
    return write_map(grid, folder, name, preview=False)


def local_path(server: SshdServer, remote: str) -> Path:
    assert remote.startswith(str(server.home) + "/"), remote
    return Path(remote)


def test_key_auth_upload_creates_folder_and_trusts_on_first_use(
    sshd_server: SshdServer, tmp_path: Path, remote_maps_dir: str
) -> None:
    files = make_map(tmp_path / "maps", "hall")
    profile = profile_for(sshd_server, tmp_path, remote_maps_dir)
    seen: list[Progress] = []
    result = upload(files, profile, progress=seen.append)

    expected_dir = sshd_server.home / remote_maps_dir.removeprefix("~/")
    assert result.remote_yaml == str(expected_dir / "hall.yaml")  # "~" expanded to the real home
    assert result.remote_image == str(expected_dir / "hall.pgm")
    assert local_path(sshd_server, result.remote_image).read_bytes() == files.image.read_bytes()
    assert local_path(sshd_server, result.remote_yaml).read_bytes() == files.yaml.read_bytes()
    assert expected_dir.stat().st_uid == os.stat(sshd_server.home).st_uid  # created by the test user
    assert sorted(p.name for p in expected_dir.iterdir()) == ["hall.pgm", "hall.yaml"]  # no .part left
    # trust on first use: recorded and reported
    assert result.host_key.newly_trusted
    assert result.host_key.fingerprint == sshd_server.host_key_fingerprint
    assert (tmp_path / "known_hosts").read_text() == sshd_server.known_hosts_line()
    # progress: the upload step, monotonic, ends at the whole of both files
    total = files.image.stat().st_size + files.yaml.stat().st_size
    assert {p.step for p in seen} == {"upload"}
    assert seen[-1] == Progress("upload", 1.0, f"{total // 1024} / {total // 1024} KiB")
    fractions = [p.fraction for p in seen]
    assert fractions == sorted(fractions) and len(seen) > 2


def test_password_auth_upload_and_known_key_accepted(
    sshd_server: SshdServer, tmp_path: Path, remote_maps_dir: str
) -> None:
    files = make_map(tmp_path / "maps", "lab", seed=1)
    profile = profile_for(sshd_server, tmp_path, remote_maps_dir, auth="password", key_file=None)
    first = upload(files, profile, password=sshd_server.password)
    assert first.host_key.newly_trusted
    files2 = make_map(tmp_path / "maps", "lab", width=50, seed=2)  # same name, new content: replaced
    second = upload(files2, profile, password=sshd_server.password)
    assert not second.host_key.newly_trusted
    assert second.host_key.fingerprint == first.host_key.fingerprint
    assert (tmp_path / "known_hosts").read_text().count("\n") == 1
    assert Path(second.remote_image).read_bytes() == files2.image.read_bytes()


def test_strict_mode_refuses_unknown_key(sshd_server: SshdServer, tmp_path: Path, remote_maps_dir: str) -> None:
    profile = profile_for(sshd_server, tmp_path, remote_maps_dir, host_key_check="strict")
    with pytest.raises(TransferError, match="unknown SSH host key") as info:
        upload_map(make_map(tmp_path, "m"), profile)
    assert sshd_server.host_key_fingerprint in str(info.value)
    assert not (tmp_path / "known_hosts").exists()
    assert not (sshd_server.home / remote_maps_dir.removeprefix("~/")).exists()
    # once the key is known, strict mode connects
    (tmp_path / "known_hosts").write_text(sshd_server.known_hosts_line())
    assert upload_map(make_map(tmp_path, "m"), profile).endswith("/ALMA_MAPS/m.yaml")


def test_changed_host_key_refused(sshd_server: SshdServer, tmp_path: Path, remote_maps_dir: str) -> None:
    other = tmp_path / "other_key"
    subprocess.run(["ssh-keygen", "-q", "-t", "ed25519", "-N", "", "-f", str(other)], check=True)
    key_type, b64 = other.with_suffix(".pub").read_text().split()[:2]
    known = tmp_path / "known_hosts"
    known.write_text(f"[{sshd_server.host}]:{sshd_server.port} {key_type} {b64}\n")
    profile = profile_for(sshd_server, tmp_path, remote_maps_dir)  # tofu: still refuses a CHANGED key
    with pytest.raises(TransferError, match="CHANGED") as info:
        upload_map(make_map(tmp_path, "m"), profile)
    assert sshd_server.host_key_fingerprint in str(info.value)
    assert "ssh-keygen -R" in str(info.value)
    assert known.read_text().split()[2] == b64  # not replaced
    assert not (sshd_server.home / remote_maps_dir.removeprefix("~/")).exists()


def test_wrong_password_is_a_clear_error(sshd_server: SshdServer, tmp_path: Path, remote_maps_dir: str) -> None:
    profile = profile_for(sshd_server, tmp_path, remote_maps_dir, auth="password", key_file=None)
    with pytest.raises(TransferError, match="authentication with password failed") as info:
        upload_map(make_map(tmp_path, "m"), profile, password="not-the-password")
    assert f"pmktest@127.0.0.1:{sshd_server.port}" in str(info.value)
    with pytest.raises(TransferError, match="a password is needed"):
        upload_map(make_map(tmp_path, "m"), profile)


def test_unauthorised_key_names_the_key(sshd_server: SshdServer, tmp_path: Path, remote_maps_dir: str) -> None:
    stranger = tmp_path / "stranger"
    subprocess.run(["ssh-keygen", "-q", "-t", "ed25519", "-N", "", "-f", str(stranger)], check=True)
    profile = profile_for(sshd_server, tmp_path, remote_maps_dir, key_file=str(stranger))
    with pytest.raises(TransferError, match=f"authentication with key file {stranger} failed"):
        upload_map(make_map(tmp_path, "m"), profile)


@pytest.mark.slow
def test_refused_and_silent_ports(sshd_server: SshdServer, tmp_path: Path) -> None:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        closed_port = probe.getsockname()[1]
    profile = profile_for(sshd_server, tmp_path, "~/x", ssh_port=closed_port)
    with pytest.raises(TransferError, match="connection refused"):
        upload_map(make_map(tmp_path, "m"), profile, timeout=3)
    with socket.socket() as silent:  # accepts TCP but never says "SSH-2.0"
        silent.bind(("127.0.0.1", 0))
        silent.listen()
        profile = profile_for(sshd_server, tmp_path, "~/x", ssh_port=silent.getsockname()[1])
        with pytest.raises(TransferError, match="within 1 s"):
            upload_map(make_map(tmp_path, "m"), profile, timeout=1)


def test_permission_denied_on_remote_folder(sshd_server: SshdServer, tmp_path: Path) -> None:
    profile = profile_for(sshd_server, tmp_path, "/etc/pmk-test-denied/ALMA_MAPS")
    with pytest.raises(TransferError, match="permission denied creating /etc/pmk-test-denied"):
        upload_map(make_map(tmp_path, "m"), profile)
    assert not Path("/etc/pmk-test-denied").exists()


@pytest.mark.slow
def test_cut_connection_leaves_previous_files_intact(
    sshd_server: SshdServer, tmp_path: Path, remote_maps_dir: str
) -> None:
    profile = profile_for(sshd_server, tmp_path, remote_maps_dir)
    old = make_map(tmp_path / "old", "big", width=20, height=20)
    remote_yaml = Path(upload_map(old, profile))
    remote_image = remote_yaml.with_name("big.pgm")
    before = (remote_yaml.read_bytes(), remote_image.read_bytes())

    new = make_map(tmp_path / "new", "big", width=2000, height=2000, seed=5)  # 4 MB: many chunks
    killed = threading.Event()

    def cut_after_first_chunk(progress: Progress) -> None:
        if progress.fraction and not killed.is_set():
            killed.set()
            for pid in sshd_server.session_pids():  # the real connection dies, like a Wi-Fi drop
                os.kill(pid, signal.SIGKILL)

    with pytest.raises(TransferError, match=r"connection lost|stopped answering"):
        upload_map(new, profile, progress=cut_after_first_chunk, timeout=5)
    assert killed.is_set()
    assert (remote_yaml.read_bytes(), remote_image.read_bytes()) == before
    leftovers = [p.name for p in remote_yaml.parent.iterdir() if p.name not in ("big.yaml", "big.pgm")]
    assert all(name.startswith(".big.pgm.part-") for name in leftovers)  # only the hidden temp file
    # the next successful upload replaces the files and sweeps the interrupted temp file away
    upload_map(new, profile)
    assert remote_image.read_bytes() == new.image.read_bytes()
    assert sorted(p.name for p in remote_yaml.parent.iterdir()) == ["big.pgm", "big.yaml"]


def test_yaml_pointing_at_absolute_image_is_rewritten(
    sshd_server: SshdServer, tmp_path: Path, remote_maps_dir: str
) -> None:
    files = make_map(tmp_path / "maps", "abs")
    doc = yaml.safe_load(files.yaml.read_text())
    doc["image"] = str(files.image)  # hand-made YAML with an absolute local path
    files.yaml.write_text(yaml.safe_dump(doc))
    remote = Path(upload_map(files, profile_for(sshd_server, tmp_path, remote_maps_dir)))
    sent = yaml.safe_load(remote.read_text())
    assert sent["image"] == "abs.pgm"
    assert sent["resolution"] == doc["resolution"]
    assert (remote.parent / "abs.pgm").read_bytes() == files.image.read_bytes()


def test_missing_image_fails_before_connecting(tmp_path: Path) -> None:
    files = make_map(tmp_path, "gone")
    files.image.unlink()
    profile = ChairProfile(name="x", host="127.0.0.1", ssh_port=1, ssh_user="u")
    with pytest.raises(TransferError, match=r"gone\.pgm does not exist"):
        upload_map(files, profile, password="pw")


def test_check_ssh_reports_folder(sshd_server: SshdServer, tmp_path: Path, remote_maps_dir: str) -> None:
    profile = profile_for(sshd_server, tmp_path, remote_maps_dir)
    check = check_ssh(profile)
    assert not check.exists
    assert check.remote_dir == str(sshd_server.home / remote_maps_dir.removeprefix("~/"))
    upload_map(make_map(tmp_path, "m"), profile)
    assert check_ssh(profile).exists


def test_disk_full_is_reported_and_previous_files_survive(
    sshd_server: SshdServer, tmp_path: Path, remote_maps_dir: str
) -> None:
    """A 96 KiB tmpfs as the chair's maps folder: the second, bigger map cannot fit."""
    folder = sshd_server.home / remote_maps_dir.removeprefix("~/")
    folder.mkdir(parents=True)
    mounted = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=96k,mode=0777", "tmpfs", str(folder)], capture_output=True, text=True
    )
    if mounted.returncode != 0:
        pytest.fail(f"cannot mount a small tmpfs for the disk-full test (needs root): {mounted.stderr.strip()}")
    try:
        profile = profile_for(sshd_server, tmp_path, remote_maps_dir)
        small = make_map(tmp_path / "small", "floor", width=40, height=40)
        remote_yaml = Path(upload_map(small, profile))
        before = (remote_yaml.read_bytes(), remote_yaml.with_name("floor.pgm").read_bytes())
        big = make_map(tmp_path / "big", "floor", width=400, height=400)  # 160 kB image
        with pytest.raises(TransferError, match="disk may be full") as info:
            upload_map(big, profile)
        assert f"{sshd_server.user}@127.0.0.1:{sshd_server.port}" in str(info.value)
        assert (remote_yaml.read_bytes(), remote_yaml.with_name("floor.pgm").read_bytes()) == before
        assert sorted(p.name for p in folder.iterdir()) == ["floor.pgm", "floor.yaml"]  # temp file removed
    finally:
        subprocess.run(["umount", str(folder)], check=False)


@pytest.mark.parametrize("form", ["absolute", "relative"])
def test_absolute_and_relative_remote_folders(
    sshd_server: SshdServer, tmp_path: Path, remote_maps_dir: str, form: str
) -> None:
    below_home = remote_maps_dir.removeprefix("~/") + f"/{form}"
    remote = str(sshd_server.home / below_home) if form == "absolute" else below_home
    result = upload_map(make_map(tmp_path, "m"), profile_for(sshd_server, tmp_path, remote))
    assert result == str(sshd_server.home / below_home / "m.yaml")
    assert Path(result).is_file()


def test_a_dot_dot_in_the_yamls_own_path_is_sent(tmp_path: Path) -> None:
    """Issue 40, item 8: `pmk send maps/../maps/m.yaml` was refused, 'image not in the YAML's folder'."""
    from pmk_nb.chair.transfer import image_beside
    from pmk_nb.rosmap import write_map
    from tests.fixtures_sim import room_grid

    files = write_map(room_grid(), tmp_path / "maps", "m", preview=False)
    (tmp_path / "other").mkdir()
    _doc, image = image_beside(tmp_path / "other" / ".." / "maps" / "m.yaml")
    assert image.resolve() == files.image.resolve()
