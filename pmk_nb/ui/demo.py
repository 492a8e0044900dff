"""Set up the ``pmk demo`` world: a converted sample map, a running simulated chair, a profile for it.

Kept apart from the CLI so the browser test can build the same world.  The simulator runs as a
``pmk sim`` child process (its own event loop and GIL, like a real chair); the dashboard's kernels
reach it through the "Simulated chair" profile written here.  The simulator gets a random SFTP
password per run, handed to the dashboard's processes in ``PMK_SIM_PASSWORD`` with the profile
name in ``PMK_SIM_PROFILE`` (:meth:`AppContext.ssh_password` honours it for that profile only): a
keyring may not exist, and the profile store's memory-only fallback does not cross processes.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pmk_nb
from pmk_nb.errors import PmkError
from pmk_nb.ui.context import DEMO_PASSWORD_ENV, DEMO_PROFILE_ENV

DEMO_PROFILE = "Simulated chair"
DEMO_RESOLUTION = 0.05
DEMO_SFTP_USER = "pmk"
SIM_START_TIMEOUT = 60.0


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
    sim: subprocess.Popen[Any] | None = None
    log_path: Path | None = None
    _log: Any = field(default=None, repr=False)

    def stop(self) -> None:
        from pmk_nb.ui.cli import stop_process

        stop_process(self.sim)
        if self._log is not None:
            with contextlib.suppress(OSError):
                self._log.close()


def sim_command(map_yaml: Path, ros_port: int, sftp_port: int, chair_dir: Path, password: str) -> list[str]:
    """``pmk sim`` for the demo: patrolling chair, SFTP with a per-run random password."""
    return [
        sys.executable, "-m", "pmk_nb.cli", "sim",
        "--map", str(map_yaml),
        "--host", "127.0.0.1",
        "--port", str(ros_port),
        "--sftp-port", str(sftp_port),
        "--sftp-user", DEMO_SFTP_USER,
        "--sftp-password", password,
        "--maps-dir", str(chair_dir),
        "--patrol",
    ]  # fmt: skip


def prepare_demo(root: Path, *, gml: Path | None = None, ip: str = "127.0.0.1") -> DemoWorld:
    """Convert the sample, start the simulator, write the profile and current map; return the world.

    Raises:
        PmkError: the sample is missing, conversion fails or the simulator does not start.
    """
    from pmk_nb.chair.settings import PROFILES_FILE, ChairProfile, ProfileStore
    from pmk_nb.library import MapsFolder
    from pmk_nb.ui.cli import free_port, stop_process, wait_for_port
    from pmk_nb.ui.context import AppContext

    root = root.expanduser().resolve()
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
    first = generated[0]

    password = secrets.token_urlsafe(16)
    ros_port, sftp_port = free_port(), free_port()
    env = dict(os.environ)
    env.update(PMK_MAPS_DIR=str(maps_dir), PMK_CONFIG_DIR=str(config_dir))
    env.update({DEMO_PROFILE_ENV: DEMO_PROFILE, DEMO_PASSWORD_ENV: password})
    log_path = root / "sim.log"
    log = log_path.open("ab")
    sim = subprocess.Popen(
        sim_command(first.yaml, ros_port, sftp_port, chair_dir, password),
        env=env, stdout=log, stderr=subprocess.STDOUT, cwd=root,
    )  # fmt: skip
    world = DemoWorld(root, maps_dir, config_dir, chair_dir, first.yaml, ros_port, sftp_port, env, sim, log_path, log)
    try:
        wait_for_port("127.0.0.1", ros_port, sim, "the simulated chair (rosbridge)", SIM_START_TIMEOUT)
        wait_for_port("127.0.0.1", sftp_port, sim, "the simulated chair (SFTP)", SIM_START_TIMEOUT)
        store = ProfileStore(config_dir / PROFILES_FILE, secrets=False)
        store.save(
            ChairProfile(
                name=DEMO_PROFILE,
                host="127.0.0.1",
                port=ros_port,
                ssh_user=DEMO_SFTP_USER,
                ssh_port=sftp_port,
                auth="password",
                known_hosts=str(config_dir / "known_hosts"),
            )
        )
        ctx = AppContext(maps, store, config_dir=config_dir)
        ctx.set_current_map(first.yaml.stem, first.yaml, first.preview)
        ctx.close()
    except BaseException:
        stop_process(sim)
        log.close()
        tail = log_path.read_text(errors="replace")[-2000:] if log_path.exists() else ""
        if tail:
            print(f"simulator log ({log_path}):\n{tail}", file=sys.stderr)
        raise
    return world
