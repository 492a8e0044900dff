"""A driving simulated chair in its own process, shared by the link and live-preview benchmarks.

The chair drives a 1 m circle in the second room (0.5 m/s, 0.5 rad/s), commanded over rosbridge from
the simulator's own process so the process under test carries no extra work.  Odometry at 50 Hz and
1080-ray scans at 40 Hz: the load a real chair's laser and base put on rosbridge.
"""

from __future__ import annotations

import contextlib
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

SIM_CODE = """
import sys, threading
from pmk_nb.chair.link.client import ChairLink
from pmk_nb.sim import SimChair, SimConfig
sim = SimChair(SimConfig(odom_rate=50.0, scan_rate=40.0, rays=1080, start_pose=(7.5, 1.5, 0.0))).start()
driver = ChairLink("127.0.0.1", sim.port)
driver.connect(timeout=10.0)
stop = threading.Event()
def drive():
    while not stop.wait(0.1):
        driver.publish_cmd_vel(0.5, 0.5)
threading.Thread(target=drive, daemon=True).start()
print(sim.port, flush=True)
sys.stdin.readline()
stop.set()
driver.close()
sim.stop()
"""


@contextlib.contextmanager
def driving_sim() -> Iterator[tuple[int, int]]:
    """Start the chair; yields (rosbridge port, simulator pid); stops it (a newline on stdin) at exit."""
    sim = subprocess.Popen(
        [sys.executable, "-c", SIM_CODE], cwd=ROOT, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True
    )
    try:
        assert sim.stdout is not None
        yield int(sim.stdout.readline().strip()), sim.pid
    finally:
        if sim.stdin is not None:
            with contextlib.suppress(OSError):
                sim.stdin.write("\n")
                sim.stdin.flush()
        try:
            sim.wait(30)
        except subprocess.TimeoutExpired:
            sim.kill()
            sim.wait()
