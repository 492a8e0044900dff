"""The world the drive browser tests and ``bench/bench_drive.py`` share.

A simulated chair in its own process (no patrol: it moves only when driven), parked in the demo
floor's corridor; the demo floor as the current map; a profile for the chair; Voilà serving the
dashboard with the preview starting by itself. :class:`ChairWatch` is a separate real roslibpy
client that records the simulator's odometry and every /cmd_vel on the wire, so latencies are
measured on the chair's side, not the page's.
"""

from __future__ import annotations

import contextlib
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pmk_nb.serve.procs import free_port, stop_process, wait_for_port
from pmk_nb.serve.voila import voila_command, write_dashboard_notebook
from pmk_nb.ui import AUTOSTART_ENV

ROOT = Path(__file__).resolve().parents[1]
SIM_CODE = """
import sys
from pmk_nb.sim import SimChair, SimConfig
from pmk_nb.sim.demo import demo_grid
sim = SimChair(SimConfig(grid=demo_grid(), port={port}, odom_rate=50.0, scan_rate=10.0, rays=360,
               start_pose=(1.0, 6.0, 0.0))).start()
print(sim.port, flush=True)
sys.stdin.readline()
sim.stop()
"""


@dataclass
class DriveWorld:
    url: str
    ros_port: int
    voila_port: int
    root: Path


@contextlib.contextmanager
def drive_world(root: Path, server: str = "voila", extra_env: dict[str, str] | None = None) -> Iterator[DriveWorld]:
    """Simulator + profile + current map + Voilà (or JupyterLab: ``server="lab"``); all stopped at exit.
    ``extra_env`` adds to the server's environment (``PMK_KIOSK=1``: kiosk pages).

    JupyterLab opens ``dashboard.ipynb`` at the yielded URL (token ``pmk-test``); run its cell.
    """
    from pmk_nb.chair import PROFILES_FILE, ChairProfile, ProfileStore
    from pmk_nb.library import MapsFolder
    from pmk_nb.rosmap import write_map
    from pmk_nb.sim import demo_grid
    from pmk_nb.ui import AppContext

    maps_dir, config_dir = root / "maps", root / "config"
    maps_dir.mkdir(parents=True, exist_ok=True)
    config_dir.mkdir(parents=True, exist_ok=True)
    ros_port = free_port()
    sim_log = (root / "sim.log").open("wb")
    sim = subprocess.Popen(
        [sys.executable, "-c", SIM_CODE.format(port=ros_port)],
        cwd=ROOT,
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=sim_log,
        text=True,
    )
    voila = None
    voila_log = (root / "voila.log").open("wb")
    try:
        wait_for_port("127.0.0.1", ros_port, sim, "the simulated chair", 60.0)
        files = write_map(demo_grid(), maps_dir, "demo_floor")
        store = ProfileStore(config_dir / PROFILES_FILE, secrets=False)
        store.save(ChairProfile(name="Simulated chair", host="127.0.0.1", port=ros_port))
        ctx = AppContext(MapsFolder(maps_dir), store, config_dir=config_dir)
        ctx.set_current_map("demo_floor", files.yaml, files.preview)
        ctx.close()
        import os

        env = {**os.environ, "PMK_MAPS_DIR": str(maps_dir), "PMK_CONFIG_DIR": str(config_dir), AUTOSTART_ENV: "1"}
        env.update(extra_env or {})
        port = free_port()
        notebook = write_dashboard_notebook(root / "kiosk")
        cmd, url = voila_command(notebook, port=port), f"http://127.0.0.1:{port}/"
        if server == "lab":
            cmd = [
                sys.executable,
                "-m",
                "jupyterlab",
                "--no-browser",
                f"--port={port}",
                "--ip=127.0.0.1",
                "--ServerApp.token=pmk-test",
                "--ServerApp.open_browser=False",
                "--allow-root",
                f"--ServerApp.root_dir={notebook.parent}",
            ]
            url = f"http://127.0.0.1:{port}/lab/tree/dashboard.ipynb?token=pmk-test"
        voila = subprocess.Popen(cmd, env=env, cwd=notebook.parent, stdout=voila_log, stderr=subprocess.STDOUT)
        wait_for_port("127.0.0.1", port, voila, server, 120.0)
        yield DriveWorld(url, ros_port, port, root)
    finally:
        stop_process(voila)
        if sim.stdin is not None:
            with contextlib.suppress(OSError):
                sim.stdin.write("\n")
                sim.stdin.flush()
        if not _waited(sim, 10.0):
            stop_process(sim)
        sim_log.close()
        voila_log.close()


def _waited(proc: subprocess.Popen[Any], seconds: float) -> bool:
    try:
        proc.wait(seconds)
        return True
    except subprocess.TimeoutExpired:
        return False


class ChairWatch:
    """The simulator's odometry (v, w) and the /cmd_vel messages, each with its arrival time."""

    def __init__(self, port: int, *, listen: bool = True) -> None:
        """``listen=False``: connect only (a load harness publishes through it and subscribes later,
        so that its own watching does not load the chairs it measures)."""
        import roslibpy

        self.ros = roslibpy.Ros("127.0.0.1", port, transport="asyncio")  # as the link (one transport per process)
        self.ros.run(10.0)
        self.odom: list[tuple[float, float, float]] = []
        self.cmds: list[tuple[float, float, float]] = []
        self._lock = threading.Lock()
        self._topics: list[Any] = []
        if listen:
            self.listen()

    def listen(self) -> None:
        """Subscribe to the odometry and /cmd_vel (once) and wait up to 10 s for the first odometry."""
        import roslibpy

        if self._topics:
            return
        self._topics = [
            roslibpy.Topic(self.ros, "/odom", "nav_msgs/Odometry", queue_length=0),
            roslibpy.Topic(self.ros, "/cmd_vel", "geometry_msgs/Twist", queue_length=0),
        ]
        self._topics[0].subscribe(self._on_odom)
        self._topics[1].subscribe(self._on_cmd)
        deadline = time.monotonic() + 10.0
        while not self.odom and time.monotonic() < deadline:
            time.sleep(0.05)

    def _on_odom(self, msg: dict[str, Any]) -> None:
        twist = msg["twist"]["twist"]
        with self._lock:
            self.odom.append((time.monotonic(), twist["linear"]["x"], twist["angular"]["z"]))
            del self.odom[:-2000]

    def _on_cmd(self, msg: dict[str, Any]) -> None:
        with self._lock:
            self.cmds.append((time.monotonic(), msg["linear"]["x"], msg["angular"]["z"]))

    def first(self, since: float, pred: Callable[[float, float], bool], timeout: float = 5.0) -> float | None:
        """Seconds from ``since`` to the first odometry after it with ``pred(v, w)``; None on timeout."""
        deadline = time.monotonic() + timeout
        while True:
            with self._lock:
                hit = next((t for t, v, w in self.odom if t >= since and pred(v, w)), None)
            if hit is not None:
                return hit - since
            if time.monotonic() > deadline:
                return None
            time.sleep(0.01)

    def cmds_since(self, since: float) -> list[tuple[float, float, float]]:
        with self._lock:
            return [c for c in self.cmds if c[0] >= since]

    def moving(self, v: float, w: float) -> bool:
        return abs(v) > 1e-3 or abs(w) > 1e-3

    def still(self, v: float, w: float) -> bool:
        return v == 0.0 and w == 0.0

    def close(self) -> None:
        for topic in self._topics:
            with contextlib.suppress(Exception):
                topic.unsubscribe()
        self.ros.factory._stop = True  # no background reconnect (roslibpy has no API for it)
        with contextlib.suppress(Exception):
            self.ros.close()
