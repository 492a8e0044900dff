"""How wide a gap between cells is still a wall (issue 31, rule 7).

A gap between two cells that no transition crosses is drawn occupied up to the thickest wall the
building has, and never less than :data:`MIN_WALL` (1 m): left unknown, it is passable to Nav2's
planners (``allow_unknown: true`` by default), so a 0.8 m gap between two rooms was a way round
every door. Wider gaps (courtyards, corridors the file leaves out) and the outside beyond that
distance stay unknown.

The thickest wall is measured where the file itself says a wall is crossed: the widest gap that a
transition's opening (rules door / line / corridor / middle) or a door line spans. Those gaps are
walls by the file's own word. The other candidate, the distribution of gaps between facing
parallel cell edges, mixes walls with corridors and light wells the file leaves out, and its widest
"wall" would be one of those; a bridge (a linked pair with nothing drawn between, up to 3 m) is a
missing landing, not a wall, so it does not count either. As transitions open walls only up to
``max_wall_gap``, the measure rarely exceeds it: in practice the floor (1 m) or a larger
``max_wall_gap`` decides, and the measure guards files whose door lines span thicker walls.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from pmk_nb.openings.model import OpeningPlan

MIN_WALL = 1.0  # metres: gaps at least this wide between cells are walls
_WALL_RULES = ("door", "line", "corridor", "middle")  # openings through a wall (not bridges, not apart)


def thickest_wall(openings: OpeningPlan, door_reach: np.ndarray, max_gap: float) -> float:
    """The widest gap between cells to draw as wall: the thickest wall the file's transitions and
    door lines cross (``door_reach``: each door line's reach to its rooms), ``max_gap``, and at least
    :data:`MIN_WALL`; 0 when ``max_gap`` is 0 (gap walls turned off)."""
    if max_gap <= 0:
        return 0.0
    crossed = [r for o in openings.openings if o.rule in _WALL_RULES for r in (o.reaches or (o.gap,))]
    doors = float(np.max(door_reach)) if len(door_reach) else 0.0
    return max(MIN_WALL, max_gap, doors, *crossed)
