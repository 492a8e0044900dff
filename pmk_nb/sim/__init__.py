"""Simulated PMK wheelchair speaking rosbridge v2 (+ SFTP): see :class:`SimChair`."""

from __future__ import annotations

from pmk_nb.sim.bridge_modes import BRIDGE_MODES, DEFAULT_BRIDGE
from pmk_nb.sim.chair import Chair
from pmk_nb.sim.demo import demo_grid, sample_floor
from pmk_nb.sim.hostkey import default_state_dir
from pmk_nb.sim.laser import Laser
from pmk_nb.sim.messages import ROS_VERSIONS
from pmk_nb.sim.server import SimChair, SimError
from pmk_nb.sim.world import World

__all__ = [
    "BRIDGE_MODES",
    "DEFAULT_BRIDGE",
    "ROS_VERSIONS",
    "Chair",
    "Laser",
    "SimChair",
    "SimError",
    "World",
    "default_state_dir",
    "demo_grid",
    "sample_floor",
]
