"""``pmk hub``'s students apart (issue 38): a system user per student, their own files, the class's folders.

Isolated (the hub runs as root, the default there): each student's server runs as their own system user
``<prefix><student>`` (created with ``useradd`` when the hub starts, removed when it stops), in a 0700
home they own; the hub's state folder (cookie secret, database, configuration) stays 0700 root. So a
student's code reads neither another student's files nor the hub's secrets. Each student's home holds
their chair's rosbridge secret and SFTP key (0600, theirs): their chair (:mod:`pmk_nb.classroom.seat`)
serves only a client holding that secret (:mod:`pmk_nb.rosauth`), so another student cannot drive it.

Shared (``--shared-user``): every server runs as the hub's user, as JupyterHub's
``SimpleLocalProcessSpawner`` does: only the browser keeps students apart, and each page says so.
Without root the hub refuses to start unless ``--shared-user`` says the class accepts that.
"""

from __future__ import annotations

import os
import pwd
import re
import shutil
import stat
import subprocess
from dataclasses import dataclass
from pathlib import Path

from pmk_nb.classroom import BRIDGE_SECRET_ENV, SEAT_DIR_ENV, SEAT_KEY_ENV, SHARED_USER_ENV
from pmk_nb.fileio import atomic_write
from pmk_nb.rosauth import new_secret
from pmk_nb.serve import serving

#: the hub's environment names the students' users' prefix to its spawner (empty: shared)
USER_PREFIX_ENV = "PMK_HUB_USER_PREFIX"
MAX_SYSTEM_NAME = 32  # useradd's limit on a user name
STUDENT_DIR = ".pmk"  # in a student's home: their secret, key, pages' settings
SECRET_FILE = "bridge_secret"
KEY_NAME = "seat_ed25519"
SEATS_DIR = "seats"
MAPS_DIR = "maps"
NOLOGIN = "/usr/sbin/nologin"


@dataclass(frozen=True)
class Isolation:
    """How the class keeps students apart: ``prefix`` of their system users, or shared (``prefix`` empty)."""

    prefix: str = ""

    @property
    def isolated(self) -> bool:
        return bool(self.prefix)

    def system_user(self, student: str) -> str | None:
        return f"{self.prefix}{student}" if self.prefix else None


def choose_isolation(shared_user: bool, prefix: str | None, class_dir: Path, users: tuple[str, ...]) -> Isolation:
    """Isolated as root unless ``--shared-user``; without root only ``--shared-user`` is allowed.

    Raises:
        ServingRefused: reason ``"no-isolation"`` (not root, no ``--shared-user``) or ``"bad-users"``
            (a system user name would be too long or not a name).
    """
    if shared_user:
        return Isolation()
    if os.geteuid() != 0:
        raise serving.ServingRefused(
            "pmk hub keeps students apart with a system user each, which needs root: run it as root, or pass "
            "--shared-user to accept a class where every student's code runs as you and can read the others' files "
            "(each page then says so)",
            ip="",
            port=None,
            reason="no-isolation",
        )
    prefix = prefix if prefix is not None else default_prefix(class_dir)
    names = [f"{prefix}{u}" for u in users]
    bad = [n for n in names if len(n) > MAX_SYSTEM_NAME or not re.match(r"^[a-z_][a-z0-9_.-]*$", n)]
    if bad:
        raise serving.ServingRefused(
            f"system user names {', '.join(bad)} are not valid (at most {MAX_SYSTEM_NAME} characters, a letter "
            "first): use a shorter --user-prefix or shorter student names",
            ip="",
            port=None,
            reason="bad-users",
        )
    return Isolation(prefix)


def default_prefix(class_dir: Path) -> str:
    """``pmk-<class>-``: the class folder's name, letters and digits only, at most 8."""
    label = re.sub(r"[^a-z0-9]", "", class_dir.name.lower())[:8] or "class"
    return f"pmk-{label}-"


def create_users(isolation: Isolation, users: tuple[str, ...], users_dir: Path) -> list[str]:
    """The students' system users that do not exist yet (home ``users_dir/<student>``, no login shell);
    returns the names created (the hub removes them when it stops)."""
    created = []
    for student in users:
        name = isolation.system_user(student)
        if name is None or _exists(name):
            continue
        home = users_dir / student
        subprocess.run(
            [
                "useradd",
                "--system",
                "--no-create-home",
                "--home-dir",
                str(home),
                "--shell",
                NOLOGIN,
                "--user-group",
                name,
            ],
            check=True,
            capture_output=True,
        )
        created.append(name)
    return created


def check_students_can_run(isolation: Isolation, student: str, env: dict[str, str]) -> None:
    """A student's user must be able to run this Python and import the dashboard and JupyterHub's server
    (an interpreter under a closed folder, e.g. root's home, is a common trap).

    Raises:
        ServingRefused: reason ``"students-cannot-run"``, with the interpreter and what failed.
    """
    import sys

    name = isolation.system_user(student)
    if name is None:
        return
    user = pwd.getpwnam(name)
    run = subprocess.run(
        [sys.executable, "-c", "import pmk_nb.classroom, jupyterhub.singleuser"],
        user=user.pw_uid,
        group=user.pw_gid,
        extra_groups=[],
        env={k: v for k, v in env.items() if k in ("PATH", "PYTHONPATH", "LANG")},
        cwd="/",
        capture_output=True,
        text=True,
        check=False,
    )
    if run.returncode != 0:
        last = (run.stderr.strip().splitlines() or ["no output"])[-1]
        raise serving.ServingRefused(
            f"the students' users cannot run {sys.executable} with PMK Notebook and JupyterHub ({last}): install "
            "them where every user can read and run them (not under /root), or pass --shared-user",
            ip="",
            port=None,
            reason="students-cannot-run",
        )


def remove_users(names: list[str]) -> None:
    """``userdel`` the users this hub created (their homes stay, re-owned at the next start)."""
    for name in names:
        subprocess.run(["userdel", name], check=False, capture_output=True)


def _exists(name: str) -> bool:
    try:
        pwd.getpwnam(name)
    except KeyError:
        return False
    return True


def check_reachable(root: Path) -> None:
    """The students' users must be able to reach the class folder (its maps, its settings).

    Raises:
        ServingRefused: reason ``"unreachable-dir"``: a folder above the class is closed to other users.
    """
    closed = [p for p in root.parents if p.exists() and not stat.S_IMODE(p.stat().st_mode) & stat.S_IXOTH]
    if closed:
        raise serving.ServingRefused(
            f"the students' users cannot reach the class folder {root}: {closed[0]} is closed to other users "
            "(choose a --hub-dir under an open folder, e.g. /srv/pmk-class)",
            ip="",
            port=None,
            reason="unreachable-dir",
        )


def lock_class_folders(root: Path, state_dir: Path, users_dir: Path, config_dir: Path, seats: Path) -> None:
    """The class's folders for isolated students: the hub's state and the class key root's alone, homes
    unlistable, the class's maps and settings readable, the chair cap's folder writable by every student."""
    root.chmod(0o711)
    state_dir.mkdir(parents=True, exist_ok=True)
    state_dir.chmod(0o700)
    config_dir.chmod(0o700)
    users_dir.mkdir(parents=True, exist_ok=True)
    users_dir.chmod(0o711)
    seats.mkdir(parents=True, exist_ok=True)
    seats.chmod(0o777)  # the cap's file and lock: every student's kernel takes and gives back seats
    for name in ("chairs.lock", "chairs.json"):
        (seats / name).touch()
        (seats / name).chmod(0o666)


def prepare_student(home: Path, owner: str | None, class_maps: Path | None) -> None:
    """A student's own files before their server starts: a new rosbridge secret and, once, an SFTP key
    pair (0600), their own maps folder (a copy of the class's); everything theirs when ``owner`` is set."""
    from pmk_nb.chair import make_key_pair

    own = home / STUDENT_DIR
    own.mkdir(parents=True, exist_ok=True, mode=0o700)
    atomic_write(own / SECRET_FILE, new_secret() + "\n", mode=0o600)
    if not (own / KEY_NAME).is_file():
        make_key_pair(own, KEY_NAME, comment="pmk-seat")
    if owner is None:
        return
    if class_maps is not None and class_maps.is_dir() and not (home / MAPS_DIR).exists():
        shutil.copytree(class_maps, home / MAPS_DIR)
    user = pwd.getpwnam(owner)
    home.chmod(0o700)
    for path in [home, *home.rglob("*")]:
        os.chown(path, user.pw_uid, user.pw_gid, follow_symlinks=False)


def student_env(home: Path, isolation: Isolation) -> dict[str, str]:
    """The variables that point a student's server at their own files (:class:`StudentFiles`)."""
    own = home / STUDENT_DIR
    env = {
        SEAT_DIR_ENV: str(own / SEATS_DIR),
        SEAT_KEY_ENV: str(own / KEY_NAME),
        BRIDGE_SECRET_ENV: str(own / SECRET_FILE),
    }
    if isolation.isolated:
        env["PMK_MAPS_DIR"] = str(home / MAPS_DIR)  # the class's maps folder is read-only to them
    else:
        env[SHARED_USER_ENV] = "1"
    return env
