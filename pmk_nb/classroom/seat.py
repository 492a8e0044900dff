"""One classroom page's own simulated chair and settings folder, living and ending with its kernel.

The chair runs inside the page's kernel (a :class:`~pmk_nb.sim.SimChair` thread on free loopback
ports, rosbridge and SFTP with the class's key), parked at the map's start spot with no patrol: it
moves only when its student drives it or sends it somewhere.  Because it is in the kernel's
process, it ends with the kernel however the kernel ends (page closed, Voilà's culling, a crash);
a kernel that ends normally also gives its seat back and removes its settings folder (``atexit``).
The page's settings folder (``pages/<pid>/`` in the class's state folder, or in the student's home in
``pmk hub``) holds one profile, for this chair only, so two pages never share a chair. In ``pmk hub``
the student's own files (:class:`~pmk_nb.classroom.settings.StudentFiles`) make the chair theirs alone:
it accepts only their SFTP key and serves rosbridge only to a client holding their secret
(:mod:`pmk_nb.rosauth`), which the profile names for the dashboard's link.
"""

from __future__ import annotations

import atexit
import os
import shutil
import threading
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from pmk_nb.classroom.cap import ChairCap
from pmk_nb.classroom.settings import ODOM_RATE, RAYS, SCAN_RATE, ClassroomSettings, StudentFiles
from pmk_nb.rosauth import read_secret

if TYPE_CHECKING:
    from pmk_nb.sim import SimChair  # imported on use at run time: the simulator is heavy

PROFILE_NAME = "My classroom chair"
SFTP_USER = "pmk"
PAGES_DIR = "pages"


@dataclass
class Seat:
    """A page's chair: ``config_dir`` is the page's settings folder, ``chair`` its simulator."""

    config_dir: Path
    chair: SimChair
    cap: ChairCap
    pid: int
    _closed: bool = field(default=False, repr=False)
    _lock: threading.Lock = field(default_factory=threading.Lock, repr=False)

    @property
    def ros_port(self) -> int:
        return self.chair.port

    @property
    def sftp_port(self) -> int:
        port = self.chair.sftp_port
        assert port is not None, "a seat's chair serves SFTP from its start"
        return port

    def close(self) -> None:
        """Stop the chair, give the seat back, remove the settings folder; runs once."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
        try:
            self.chair.stop()
        finally:
            self.cap.release(self.pid)
            shutil.rmtree(self.config_dir, ignore_errors=True)


def take_seat(settings: ClassroomSettings) -> Seat:
    """Hold a seat, start this kernel's chair and write its profile; the seat ends with the kernel.

    Raises:
        ClassroomFull: the class's cap is reached (nothing was started).
        SimError: the simulator could not start (the seat is given back).
    """
    from pmk_nb.sim import SimChair, SimConfig

    pid = os.getpid()
    own = StudentFiles.from_env()
    secret = read_secret(own.secret_file) if own.secret_file else None  # OSError: not this student's
    public_key = f"{own.private_key}.pub" if own.private_key else settings.public_key
    cap = ChairCap(Path(settings.state_dir), settings.max_chairs)
    cap.take(pid)
    config_dir = (own.pages_dir or Path(settings.state_dir) / PAGES_DIR) / str(pid)
    _remove_dead_pages(config_dir.parent, cap)
    try:
        shutil.rmtree(config_dir, ignore_errors=True)  # a previous kernel with the same pid
        config_dir.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
        (config_dir / "chair_maps").mkdir(parents=True, mode=0o700)
        chair = SimChair(
            SimConfig(
                map_yaml=settings.map_yaml,
                port=0,
                sftp_port=0,
                sftp_user=SFTP_USER,
                sftp_authorized_key=public_key,
                auth_secret=secret,
                sftp_password_login=False,
                maps_dir=config_dir / "chair_maps",
                patrol=False,
                odom_rate=ODOM_RATE,
                scan_rate=SCAN_RATE,
                rays=RAYS,
            )
        ).start()
    except BaseException:
        cap.release(pid)
        shutil.rmtree(config_dir, ignore_errors=True)
        raise
    seat = Seat(config_dir, chair, cap, pid)
    atexit.register(seat.close)
    try:
        _write_profile(seat, str(own.private_key or settings.private_key), own.secret_file)
        cap.note(pid, ros_port=seat.ros_port, sftp_port=seat.sftp_port, user=os.environ.get("JUPYTERHUB_USER", ""))
    except BaseException:
        seat.close()
        raise
    return seat


def _write_profile(seat: Seat, private_key: str, secret_file: Path | None) -> None:
    from pmk_nb.chair import PROFILES_FILE, ChairProfile, ProfileStore

    store = ProfileStore(seat.config_dir / PROFILES_FILE, secrets=False)
    store.save(
        ChairProfile(
            name=PROFILE_NAME,
            host="127.0.0.1",
            port=seat.ros_port,
            ssh_user=SFTP_USER,
            ssh_port=seat.sftp_port,
            auth="key",
            key_file=private_key,
            known_hosts=str(seat.config_dir / "known_hosts"),
            bridge_secret_file=str(secret_file) if secret_file else None,
        )
    )


def _remove_dead_pages(pages: Path, cap: ChairCap) -> None:
    """Settings folders of kernels that ended without cleaning up (killed): their pid holds no seat."""
    if not pages.is_dir():
        return
    live = {str(pid) for pid in cap.live()}
    for folder in pages.iterdir():
        if folder.name.isdigit() and folder.name not in live:
            shutil.rmtree(folder, ignore_errors=True)
