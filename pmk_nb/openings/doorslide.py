"""Where on a shared wall a door the file does not draw goes (rules ``line`` and ``middle``).

A transition says two cells are joined, not where the door is. The opening must be a door's width
on one straight stretch of the shared boundary, clear of its ends: a stretch ends at a corner (the
boundary turns, as round a room drawn inside another) or where a crossing wall meets it, and a
window laid round a corner or into a crossing wall is narrower than its length (FZK-Haus's attic:
0.9 m laid round a corner gave 0.63 m clear). So the window slides along the stretch until it is
``inset`` clear of both ends (as far as the stretch allows); where no stretch is as long as the door,
it takes the longest one whole - the opening clears the wall bands of its jambs, so the grid keeps
its length less a cell (FJK-Haus's 0.78 m wall niches) - and that shorter length is the clear width
the report names.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import shapely
from shapely import ops

from pmk_nb.defaults import DEFAULT_WALL_THICKNESS

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

DEFAULT_INSET = DEFAULT_WALL_THICKNESS / 2  # metres kept clear at each end of a stretch: half the default wall
_COS = math.cos(math.radians(3.0))  # segments within 3 degrees of each other are one straight stretch


def straight_pieces(run: BaseGeometry) -> list[shapely.LineString]:
    """``run`` cut at every corner into straight LineStrings (a closed run is cut at a corner too)."""
    xy = shapely.get_coordinates(run)
    if len(xy) < 2:
        return []
    d = np.diff(xy, axis=0)
    n = np.hypot(d[:, 0], d[:, 1])
    keep = n > 1e-12
    xy = np.vstack([xy[:1], xy[1:][keep]])
    if len(xy) < 2:
        return []
    d = np.diff(xy, axis=0)
    u = d / np.hypot(d[:, 0], d[:, 1])[:, None]
    turns = np.flatnonzero((u[1:] * u[:-1]).sum(axis=1) < _COS) + 1  # vertex indices where it turns
    closed = bool(np.allclose(xy[0], xy[-1])) and len(xy) > 3
    if closed and len(turns) and float((u[0] * u[-1]).sum()) >= _COS:  # the closing vertex is no corner
        xy = np.vstack([xy[turns[0] :], xy[1 : turns[0] + 1]])
        return straight_pieces(shapely.LineString(xy))
    cuts = [0, *turns.tolist(), len(xy) - 1]
    return [shapely.LineString(xy[[a, b]]) for a, b in itertools.pairwise(cuts)]


def place(runs: Sequence[BaseGeometry], width: float, inset: float, at: shapely.Point | None = None) -> BaseGeometry:
    """A ``width`` opening on one straight piece of ``runs``, ``inset`` clear of the piece's ends.

    ``at`` (where the transition's line crosses the wall): the fitting piece whose window lies nearest
    it, the window as near it as the piece allows; else the middle of the longest piece. With no piece
    long enough, the longest piece whole: narrower than ``width``, and measured so."""
    pieces = [p for run in runs for p in straight_pieces(run)]
    if not pieces:
        return runs[0]
    fits = [p for p in pieces if p.length >= width - 1e-9]
    if not fits:
        return max(pieces, key=lambda g: g.length)
    if at is None:
        p = max(fits, key=lambda g: g.length)
        return _window(p, p.length / 2, width, inset)
    windows = [_window(p, p.project(at), width, inset) for p in fits]
    return min(windows, key=lambda w: w.distance(at))


def _window(piece: shapely.LineString, centre: float, width: float, inset: float) -> BaseGeometry:
    """``width`` of ``piece`` around ``centre``, ``inset`` clear of its ends, or centred if it is shorter."""
    keep = min(inset, (piece.length - width) / 2)
    start = min(max(centre - width / 2, keep), piece.length - keep - width)
    return ops.substring(piece, start, start + width)
