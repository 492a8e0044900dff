"""Simulated PMK wheelchair speaking rosbridge v2 (+ SFTP): see :class:`SimChair`."""

from __future__ import annotations

from pmk_nb.sim.server import SimChair, SimError

__all__ = ["SimChair", "SimError"]
