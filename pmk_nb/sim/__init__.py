"""Simulated PMK wheelchair speaking rosbridge v2 (+ SFTP): see :class:`SimChair`.

The face is lazy: a name loads only its own module. The ROS 2 sim node imports the physics
(``Chair``, ``Laser``, ``World``) in a ROS environment that has no asyncssh (the SFTP side's library).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pmk_nb.lazyface import lazy_face

if TYPE_CHECKING:
    from pmk_nb.sim.bridge_modes import BRIDGE_MODES, DEFAULT_BRIDGE
    from pmk_nb.sim.chair import Chair
    from pmk_nb.sim.config import SimConfig
    from pmk_nb.sim.demo import demo_grid, sample_floor
    from pmk_nb.sim.hostkey import default_state_dir
    from pmk_nb.sim.laser import Laser
    from pmk_nb.sim.messages import ROS_VERSIONS
    from pmk_nb.sim.server import PORT_IN_USE_EXIT, SimChair, SimError, SimPortInUse
    from pmk_nb.sim.world import World

_WHERE = {
    "BRIDGE_MODES": "bridge_modes",
    "DEFAULT_BRIDGE": "bridge_modes",
    "Chair": "chair",
    "SimConfig": "config",
    "demo_grid": "demo",
    "sample_floor": "demo",
    "default_state_dir": "hostkey",
    "Laser": "laser",
    "ROS_VERSIONS": "messages",
    "SimChair": "server",
    "SimError": "server",
    "SimPortInUse": "server",
    "PORT_IN_USE_EXIT": "server",
    "World": "world",
}

__all__ = [
    "BRIDGE_MODES",
    "DEFAULT_BRIDGE",
    "PORT_IN_USE_EXIT",
    "ROS_VERSIONS",
    "Chair",
    "Laser",
    "SimChair",
    "SimConfig",
    "SimError",
    "SimPortInUse",
    "World",
    "default_state_dir",
    "demo_grid",
    "sample_floor",
]


__getattr__, __dir__ = lazy_face(__name__, _WHERE, __all__)
