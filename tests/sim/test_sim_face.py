"""The simulator's face is lazy: the ROS 2 sim node (`pmk robot sim-node`) imports the physics in a ROS
environment without asyncssh, the SFTP side's library. An eager face broke every real-stack test."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from pmk_nb.sim import World

ROOT = Path(__file__).resolve().parents[2]
BLOCKED = ("asyncssh", "paramiko", "roslibpy", "ipywidgets")


def test_the_physics_and_the_sim_node_import_without_the_network_libraries() -> None:
    code = (
        "import sys\n"
        f"for name in {BLOCKED!r}: sys.modules[name] = None  # importing it raises ImportError\n"
        "from pmk_nb.sim import Chair, Laser, World, demo_grid\n"
        "import pmk_nb.robot.simnode\n"
        "print(World.__module__)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.strip() == World.__module__ == "pmk_nb.sim.world"
