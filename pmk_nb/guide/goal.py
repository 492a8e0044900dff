"""Where in a room to send the chair: a free map cell well inside the room's polygon.

A room's centre may be under a desk or in a doorway's corner, so the goal is the free pixel of the
room nearest its centre among those with the most clearance up to ``clearance`` metres (the room's
free pixels eroded by a disc, as the accessibility check does for the chair's centre).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import shapely

from pmk_nb.access import disc_radius_px, erode
from pmk_nb.grid import FREE

if TYPE_CHECKING:
    from pmk_nb.guide.rooms import Room, RoomsMap

DEFAULT_CLEARANCE = 1.0  # metres from walls and furniture, when the room allows


def room_free_pixels(rooms: RoomsMap, room: Room) -> tuple[np.ndarray, int, int]:
    """(mask, row0, col0): the room's free pixels in the crop of the grid around its polygon."""
    grid = rooms.grid
    res, (ox, oy) = grid.resolution, (float(grid.origin[0]), float(grid.origin[1]))
    x0, y0, x1, y1 = room.polygon.bounds
    c0, c1 = max(0, math.floor((x0 - ox) / res)), min(grid.width, math.ceil((x1 - ox) / res))
    r0, r1 = max(0, math.floor((y0 - oy) / res)), min(grid.height, math.ceil((y1 - oy) / res))
    if c1 <= c0 or r1 <= r0:
        return np.zeros((0, 0), dtype=bool), r0, c0
    mask = np.asarray(grid.data)[r0:r1, c0:c1] == FREE
    rows, cols = np.nonzero(mask)  # only free pixels can count: the polygon test is the costly part
    mask[rows, cols] = shapely.contains_xy(room.polygon, ox + (cols + c0 + 0.5) * res, oy + (rows + r0 + 0.5) * res)
    return mask, r0, c0


def goal_in_room(
    rooms: RoomsMap, room: Room, chair_width: float, clearance: float = DEFAULT_CLEARANCE
) -> tuple[float, float] | None:
    """A point for the chair's centre inside ``room`` (map frame, metres), or None when no free pixel
    of the room leaves the chair's half-width clear (the room is too small or not in the map)."""
    mask, r0, c0 = room_free_pixels(rooms, room)
    res = rooms.grid.resolution
    lo, hi = disc_radius_px(chair_width / 2, res), max(disc_radius_px(clearance, res), 1.0)
    best = erode(mask, lo) if mask.size else mask
    if not best.any():
        return None
    if hi > lo:
        deeper = erode(mask, hi)
        if deeper.any():
            best = deeper
        else:  # the most clearance the room allows: bisect between the chair's radius and ``clearance``
            for _ in range(6):
                mid = (lo + hi) / 2
                cand = erode(mask, mid)
                lo, hi, best = (mid, hi, cand) if cand.any() else (lo, mid, best)
    rows, cols = np.nonzero(best)
    xs = float(rooms.grid.origin[0]) + (cols + c0 + 0.5) * res
    ys = float(rooms.grid.origin[1]) + (rows + r0 + 0.5) * res
    centre = room.polygon.centroid
    if not room.polygon.contains(centre):
        centre = room.polygon.representative_point()
    i = int(np.argmin((xs - centre.x) ** 2 + (ys - centre.y) ** 2))
    return round(float(xs[i]), 3), round(float(ys[i]), 3)
