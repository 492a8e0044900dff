"""Set up the ``pmk demo`` world: a converted sample map, a running simulated chair, a profile for it.

Kept apart from the CLI so the browser test can build the same world.  The simulator runs as a
``pmk sim`` child process (its own event loop and GIL, like a real chair); the dashboard's kernels
reach it through the "Simulated chair" profile written here.

SFTP logins use an ed25519 key pair made for each run in the demo folder (``chair_key``, mode
0600, and ``chair_key.pub``, the simulator's authorised key); the simulator refuses passwords.
That is how a hardened chair is set up, and no secret travels through environment variables or
command lines (a keyring may not exist, and the profile store never writes passwords to disk).
The dashboard is told to start the Home preview by itself (``PMK_AUTOSTART_PREVIEW``), so a
first-time user sees the chair moving without pressing anything.
"""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, TYPE_CHECKING

import pmk_nb
from pmk_nb.cli.options import DEFAULT_RESOLUTION
from pmk_nb.errors import PmkError
from pmk_nb.serve import free_port, stop_process, wait_for_port
from pmk_nb.ui import AUTOSTART_ENV

if TYPE_CHECKING:
    from pmk_nb.library import GeneratedMap, MapsFolder

DEMO_PROFILE = "Simulated chair"
DEMO_RESOLUTION = DEFAULT_RESOLUTION
DEMO_SFTP_USER = "pmk"
SIM_START_TIMEOUT = 60.0
PORT_TRIES = 3  # starts of the simulator on fresh ports when one it was given was taken meanwhile
KEY_NAME = "chair_key"


def sample_gml() -> Path:
    """``sample_maps/clinic_floor.gml`` of the source tree (not shipped in wheels)."""
    return Path(pmk_nb.__file__).resolve().parents[1] / "sample_maps" / "clinic_floor.gml"


@dataclass
class DemoWorld:
    """What :func:`prepare_demo` started; ``stop()`` ends the simulator."""

    root: Path
    maps_dir: Path
    config_dir: Path
    chair_dir: Path
    map_yaml: Path
    ros_port: int
    sftp_port: int
    env: dict[str, str]
    sim: subprocess.Popen[bytes] | None = None
    log_path: Path | None = None
    _log: IO[bytes] | None = field(default=None, repr=False)

    def stop(self) -> None:
        stop_process(self.sim)
        if self._log is not None:
            with contextlib.suppress(OSError):
                self._log.close()


def sim_command(
    map_yaml: Path, ros_port: int, sftp_port: int, chair_dir: Path, public_key: Path, extra: Sequence[str] = ()
) -> list[str]:
    """``pmk sim`` for the demo: patrolling chair, SFTP by key only (``public_key`` may log in).

    ``extra`` adds ``pmk sim`` options (e.g. ``--laser-blind=-20:40`` to show a blind laser).
    """
    return [
        sys.executable,
        "-m",
        "pmk_nb.cli",
        "sim",
        "--map",
        str(map_yaml),
        "--host",
        "127.0.0.1",
        "--port",
        str(ros_port),
        "--sftp-port",
        str(sftp_port),
        "--sftp-user",
        DEMO_SFTP_USER,
        "--sftp-authorized-key",
        str(public_key),
        "--no-sftp-password",
        "--maps-dir",
        str(chair_dir),
        "--state-dir",
        str(chair_dir.parent / "sim_state"),  # same host key after a restart (issue 29)
        "--patrol",
        *extra,
    ]


def make_key_pair(directory: Path, name: str = KEY_NAME) -> tuple[Path, Path]:
    """A new ed25519 key pair for the demo chair (:func:`pmk_nb.chair.keysetup.make_key_pair`)."""
    from pmk_nb.chair import make_key_pair as make_pair

    return make_pair(directory, name, comment="pmk-demo")


def convert_sample(root: Path, gml: Path | None = None) -> tuple[MapsFolder, GeneratedMap]:
    """Make the demo's folders (``maps``, ``config``, ``chair_maps``) and convert the sample (or ``gml``).

    Returns (the :class:`~pmk_nb.library.folder.MapsFolder`, its first generated map).

    Raises:
        PmkError: the sample is missing or conversion produces no map.
    """
    from pmk_nb.library import MapsFolder

    source = (gml or sample_gml()).expanduser()
    if not source.is_file():
        raise PmkError(f"demo map {source} not found: pass --gml with an IndoorGML file")
    maps_dir, config_dir, chair_dir = root / "maps", root / "config", root / "chair_maps"
    for d in (maps_dir, config_dir, chair_dir):
        d.mkdir(parents=True, exist_ok=True)
    # the simulator makes a new host key per run: forget the previous run's, or SFTP would refuse it
    (config_dir / "known_hosts").unlink(missing_ok=True)
    maps = MapsFolder(maps_dir)
    entry = maps.import_file(source, overwrite=True)
    generated = maps.convert(entry.name, DEMO_RESOLUTION)
    if not generated:
        raise PmkError(f"{source}: conversion produced no map")
    return maps, generated[0]


def prepare_demo(
    root: Path, *, gml: Path | None = None, ip: str = "127.0.0.1", sim_args: Sequence[str] = ()
) -> DemoWorld:
    """Convert the sample, start the simulator, write the profile and current map; return the world.

    Raises:
        PmkError: the sample is missing, conversion fails or the simulator does not start.
    """
    from pmk_nb.chair import PROFILES_FILE, ChairProfile, ProfileStore
    from pmk_nb.ui import AppContext

    root = root.expanduser().resolve()
    maps_dir, config_dir, chair_dir = root / "maps", root / "config", root / "chair_maps"
    maps, first = convert_sample(root, gml)

    private_key, public_key = make_key_pair(config_dir)
    env = dict(os.environ)
    env.update({"PMK_MAPS_DIR": str(maps_dir), "PMK_CONFIG_DIR": str(config_dir), AUTOSTART_ENV: "1"})
    log_path = root / "sim.log"
    log = log_path.open("ab")
    try:
        sim, ros_port, sftp_port = _start_sim(
            sim_command_for=lambda ros, sftp: sim_command(first.yaml, ros, sftp, chair_dir, public_key, sim_args),
            env=env,
            log=log,
            cwd=root,
        )
    except BaseException:
        log.close()
        _print_log_tail(log_path)
        raise
    world = DemoWorld(root, maps_dir, config_dir, chair_dir, first.yaml, ros_port, sftp_port, env, sim, log_path, log)
    try:
        store = ProfileStore(config_dir / PROFILES_FILE, secrets=False)
        store.save(
            ChairProfile(
                name=DEMO_PROFILE,
                host="127.0.0.1",
                port=ros_port,
                ssh_user=DEMO_SFTP_USER,
                ssh_port=sftp_port,
                auth="key",
                key_file=str(private_key),
                known_hosts=str(config_dir / "known_hosts"),
            )
        )
        ctx = AppContext(maps, store, config_dir=config_dir)
        ctx.set_current_map(first.yaml.stem, first.yaml, first.preview)
        ctx.close()
    except BaseException:
        stop_process(sim)
        log.close()
        _print_log_tail(log_path)
        raise
    return world


def _print_log_tail(log_path: Path) -> None:
    tail = log_path.read_text(errors="replace")[-2000:] if log_path.exists() else ""
    if tail:
        print(f"simulator log ({log_path}):\n{tail}", file=sys.stderr)


def _start_sim(
    *, sim_command_for: Callable[[int, int], list[str]], env: dict[str, str], log: IO[bytes], cwd: Path
) -> tuple[subprocess.Popen[bytes], int, int]:
    """Start ``pmk sim`` on two free ports and wait until both listen; (process, rosbridge, SFTP port).

    A free port found here may be taken by another program before the simulator binds it (tests and
    servers start side by side): the simulator then exits with PORT_IN_USE_EXIT and starts again on
    other ports, up to PORT_TRIES times.  Any other failure raises at once.
    """
    from pmk_nb.sim import PORT_IN_USE_EXIT

    for attempt in range(1, PORT_TRIES + 1):
        ros_port, sftp_port = free_port(), free_port()
        sim = subprocess.Popen(
            sim_command_for(ros_port, sftp_port), env=env, stdout=log, stderr=subprocess.STDOUT, cwd=cwd
        )
        try:
            wait_for_port("127.0.0.1", ros_port, sim, "the simulated chair (rosbridge)", SIM_START_TIMEOUT)
            wait_for_port("127.0.0.1", sftp_port, sim, "the simulated chair (SFTP)", SIM_START_TIMEOUT)
        except BaseException:
            stop_process(sim)
            if sim.returncode == PORT_IN_USE_EXIT and attempt < PORT_TRIES:
                continue
            raise
        return sim, ros_port, sftp_port
    raise AssertionError("unreachable: the last attempt returns or raises")
