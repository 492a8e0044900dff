"""The SHA-256 that confirms a deploy: the PMK map server reports it in MapInfo for the map it
loaded, the dashboard computes it for the map it sent, and equal hashes mean the chair publishes
our cells without ``/map`` crossing the wire. Both sides must hash the same bytes: this is them.
"""

from __future__ import annotations

import hashlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pmk_nb.grid import OccupancyGrid


def grid_sha256(grid: OccupancyGrid) -> str:
    """Hex SHA-256 of the int8 cells in ROS order (row 0 = bottom), as ``/map`` carries them."""
    return hashlib.sha256(grid.data.astype("int8", copy=False).tobytes()).hexdigest()
