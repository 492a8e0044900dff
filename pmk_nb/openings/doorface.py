"""A door cell's face towards a room it opens into, found by direction, for doors drawn a little askew.

The shared boundary of two cells is the part of one outline within the gap between them (plus a
tolerance). A door cell drawn a few degrees off its wall, or a few centimetres off it at one end, meets
that test along a fraction of its width only: the opening came out 0.4 m wide in a 0.94 m door, and
the report named it narrower than the chair (pgrouting PUN-IT, 24 such doors). So a door's opening
is its face instead: the edges of its outline along the door's width that run along the room (their
distance to it changes by at most half their length) and stay within the gap plus half the door's depth
of it. The face only ever widens an opening, and only where door and room do not overlap (a door cell
drawn across a wall keeps the boundary it shares with each room).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import shapely
from shapely import ops

from pmk_nb.geometry import boxes_overlap, door_frame, polygons_of

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

_TURN = 0.5  # an edge whose distance to the room changes by more than this share of its length is a jamb
_LONG = 1.5  # a door cell is at least this much wider than deep (else it has no clear wall direction)
_PARALLEL = 0.87  # a face edge runs within 30 degrees of the door's width


def door_face(door: BaseGeometry, room: BaseGeometry, gap: float, limit: float, tol: float) -> BaseGeometry:
    """The edges of ``door``'s outline that face ``room`` (merged lines): along the door's width, within
    ``gap`` plus half the door's depth of the room, ``limit`` at most. Empty when there are none, when
    the two overlap by more than a sliver, or when the cell is not clearly wider than deep."""
    empty = shapely.MultiLineString()
    if boxes_overlap(door, room) and shapely.intersection(door, room).area > tol * door.length:
        return empty
    frame = door_frame(door)
    if frame is None:
        return empty
    _, across, along = frame
    depth, width = float(np.hypot(*across)), float(np.hypot(*along))
    if width < _LONG * depth:
        return empty  # no clear wall direction (a square cell): the shared boundary stands
    axis = along / width
    reach = min(gap + max(depth / 2, tol), limit)
    found = []
    for part in polygons_of(door):
        xy = shapely.get_coordinates(part.exterior)
        if len(xy) < 2:
            continue
        d = np.asarray(shapely.distance(shapely.points(xy), room))
        length = np.hypot(*(xy[1:] - xy[:-1]).T)
        near = np.maximum(d[:-1], d[1:]) <= reach
        step = xy[1:] - xy[:-1]
        along = (np.abs(d[1:] - d[:-1]) <= _TURN * length) & (np.abs(step @ axis) >= _PARALLEL * length)
        for i in np.flatnonzero(near & along & (length > tol)).tolist():
            found.append(shapely.LineString(xy[i : i + 2]))
    if not found:
        return empty
    return ops.linemerge(shapely.MultiLineString(found))
