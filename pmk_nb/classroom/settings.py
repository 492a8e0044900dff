"""The class's settings file, written once by ``pmk demo --classroom`` / ``pmk hub``, read by each kernel.

A file, not a handful of environment variables: a JupyterHub single-user server passes on only the
variables its spawner names, and one variable (:data:`CLASSROOM_ENV`, the file's path) is easy to
pass.  The file holds no secret: the SFTP private key stays in its own 0600 file beside it.
"""

from __future__ import annotations

import json
import os
from dataclasses import asdict, dataclass
from pathlib import Path

from pmk_nb.errors import SettingsError
from pmk_nb.fileio import atomic_write

CLASSROOM_ENV = "PMK_CLASSROOM"
#: a student's own files, set by ``pmk hub`` for each student's server (:class:`StudentFiles`)
SEAT_DIR_ENV = "PMK_SEAT_DIR"
SEAT_KEY_ENV = "PMK_SEAT_KEY"
BRIDGE_SECRET_ENV = "PMK_BRIDGE_SECRET_FILE"
#: set by ``pmk hub --shared-user``: every student runs as one user, and the page says so
SHARED_USER_ENV = "PMK_HUB_SHARED_USER"
SETTINGS_FILE = "classroom.json"
#: the simulator's rates on a classroom page (the standalone simulator's defaults: 50 Hz, 20 Hz, 720
#: rays): many chairs share a few cores, and the page says so.  15 Hz odometry still gives the live
#: view (at most LIVE_FPS frames, drawn on change) a new pose for every frame of a moving chair.
ODOM_RATE = 15.0
SCAN_RATE = 5.0
RAYS = 360
#: the live view's frame cap on a classroom page (elsewhere 32): ten pages with their browsers share
#: two cores (bench/soak_classroom.py measured what each frame costs the kernel and the browser).
#: 11, not 12: on a full machine the pages that could draw 12 took the time of the slowest, which
#: fell under 10 in one soak of four; at 11 every page keeps a tenth above the class's goal of 10.
LIVE_FPS = 11.0


@dataclass(frozen=True)
class ClassroomSettings:
    """What every chair of the class shares.

    Attributes:
        map_yaml: the map each chair starts on (and the page's current map).
        map_name, map_preview: the page's current map as the Home screen shows it.
        public_key, private_key: the SFTP key pair (the chair accepts the first, the profile uses the second).
        max_chairs: how many chairs may run at once across the class.
        state_dir: the folder of the cap's file and the pages' settings folders.
    """

    map_yaml: str
    map_name: str
    map_preview: str | None
    public_key: str
    private_key: str
    max_chairs: int
    state_dir: str

    def write(self, path: Path) -> Path:
        atomic_write(path, json.dumps(asdict(self), indent=1) + "\n", mode=0o644, mkdir=True)
        return path

    @classmethod
    def read(cls, path: Path) -> ClassroomSettings:
        """Raises SettingsError: the file is missing or not a classroom settings file."""
        try:
            raw = json.loads(path.read_text(encoding="utf-8"))
            settings = cls(**raw)
        except (OSError, ValueError, TypeError) as err:
            raise SettingsError(f"{path}: cannot read the classroom settings ({err})") from err
        if int(settings.max_chairs) < 1:
            raise SettingsError(f"{path}: max_chairs must be at least 1, not {settings.max_chairs}")
        return settings


def from_env(env: dict[str, str] | None = None) -> ClassroomSettings | None:
    """The class's settings when this kernel serves a classroom page (:data:`CLASSROOM_ENV` set), else None."""
    value = (os.environ if env is None else env).get(CLASSROOM_ENV, "").strip()
    return ClassroomSettings.read(Path(value)) if value else None


@dataclass(frozen=True)
class StudentFiles:
    """One student's own files in a hub (their home, readable only by them when the hub isolates):

    Attributes:
        pages_dir: where their pages' settings folders go (else the class's state folder).
        private_key: their SFTP key (the public one beside it, ``.pub``): their chair accepts only it.
        secret_file: their chair's rosbridge secret (:mod:`pmk_nb.rosauth`): their chair serves only it.
    """

    pages_dir: Path | None = None
    private_key: Path | None = None
    secret_file: Path | None = None

    @classmethod
    def from_env(cls, env: dict[str, str] | None = None) -> StudentFiles:
        values = os.environ if env is None else env

        def path(name: str) -> Path | None:
            text = values.get(name, "").strip()
            return Path(text) if text else None

        return cls(path(SEAT_DIR_ENV), path(SEAT_KEY_ENV), path(BRIDGE_SECRET_ENV))


def shared_user(env: dict[str, str] | None = None) -> bool:
    """Whether this class runs every student as one user (``pmk hub --shared-user``): no isolation."""
    return (os.environ if env is None else env).get(SHARED_USER_ENV, "") == "1"
