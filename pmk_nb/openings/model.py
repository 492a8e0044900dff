"""What :func:`~pmk_nb.openings.plan.plan_openings` returns: an :class:`Opening` per link, the links it
left :class:`Skipped`, and a storey's :class:`OpeningPlan`.

Apart from the rules so that the steps the planner calls (``slab``, ``thickness``) can take a plan
or an opening without importing the planner.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import shapely

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from pmk_nb.indoorgml import Boundary, Link

_HOOK = 0.03  # metres: an end edge this short is the shared boundary's tolerance turning round a jamb


@dataclass(frozen=True)
class Opening:
    """The opening of one link: where (``segments``, on the shared boundary), how wide, and by which rule."""

    link: Link
    rule: str  # one of RULES, or "apart" when the cells are further apart than max_gap
    segments: tuple[BaseGeometry, ...]  # LineStrings along the shared boundary (metres)
    width: float  # metres along the wall (the narrowest segment)
    gap: float  # metres between the two cells (0 when they touch)
    names: tuple[str, str]
    reaches: tuple[float, ...] = ()  # per segment: how far the other cell is from it (the local gap)
    path: BaseGeometry | None = None  # rule "bridge": the passage's centre line, from cell to cell

    def polygons(self, reach: float, slack: float = 0.0) -> list[BaseGeometry]:
        """Rectangles to clear: each segment widened by its local gap plus ``reach`` on both sides, and
        ``slack`` longer at each end (a cell, so rounding at the jambs never narrows the door); for a
        bridge, the passage ``width`` wide, ``reach`` into both cells."""
        if self.path is not None:
            return [shapely.buffer(_extend(self.path, reach), self.width / 2, cap_style="flat")]
        gaps = self.reaches or (self.gap,) * len(self.segments)
        out = [
            shapely.buffer(_extend(_unhooked(s), slack), g + reach, cap_style="flat")
            for s, g in zip(self.segments, gaps, strict=True)
        ]
        return [p for p in out if not p.is_empty]


def _unhooked(line: BaseGeometry) -> BaseGeometry:
    """``line`` without the short end edges that the shared-boundary tolerance picks up around a jamb:
    a flat cap follows the last edge, so a hook of a centimetre would turn the cap and leave the
    jamb's corner of the opening walled."""
    xy = shapely.get_coordinates(line)
    lo, hi = 0, len(xy) - 1
    while hi - lo > 1 and float(((xy[lo + 1] - xy[lo]) ** 2).sum()) < _HOOK**2:
        lo += 1
    while hi - lo > 1 and float(((xy[hi] - xy[hi - 1]) ** 2).sum()) < _HOOK**2:
        hi -= 1
    return line if (lo, hi) == (0, len(xy) - 1) else shapely.LineString(xy[lo : hi + 1])


def _extend(line: BaseGeometry, by: float) -> BaseGeometry:
    """``line`` made ``by`` longer at both ends, along its first and last edges."""
    xy = shapely.get_coordinates(line)
    if by <= 0 or len(xy) < 2:
        return line
    out = xy.copy()
    for end, nxt in ((0, 1), (-1, -2)):
        d = xy[end] - xy[nxt]
        n = float((d**2).sum() ** 0.5)
        if n > 0:
            out[end] = xy[end] + d / n * by
    return shapely.LineString(out)


SKIP_WINDOW = "window"  # a cell the reader judged a window/sill from its floor height (Cell.window)
SKIP_DECLARED = "non-navigable"  # a cell the file itself declares non-navigable


@dataclass(frozen=True)
class Skipped:
    """A same-storey link left without an opening because a cell is not free: named, so the check can
    say which transitions it did not test instead of dropping them unseen."""

    link: Link
    names: tuple[str, str]
    reason: str  # SKIP_WINDOW when every non-free cell of the link is a judged window, else SKIP_DECLARED


@dataclass(frozen=True)
class OpeningPlan:
    """A storey's openings, and the door boundaries the graph leaves shut (doors with no transition)."""

    openings: list[Opening]
    shut_doors: list[Boundary]
    graph: bool  # False when no transition joins two free cells of this storey (old door rules apply)
    seams: tuple[BaseGeometry, ...] = ()  # where two free cells the graph does not join touch (metres)
    skipped: tuple[Skipped, ...] = ()  # links to a non-free cell: no opening, not checked

    def rule_counts(self) -> dict[str, int]:
        return dict(Counter(o.rule for o in self.openings))

    @property
    def links(self) -> list[Link]:
        """The storey's links when the graph decides (opened or skipped), else none."""
        return [o.link for o in self.openings] + [k.link for k in self.skipped] if self.graph else []

    def wall_polygons(self, reach: float) -> list[BaseGeometry]:
        """:meth:`Opening.polygons` of every opening cut in a wall (not a bridge), in order: the same
        rectangles, buffered in one array call (a call each was a tenth of a large storey's doors step)."""
        lines, widths = [], []
        for o in self.openings:
            if o.path is None:
                lines += [_extend(_unhooked(s), 0.0) for s in o.segments]
                widths += [g + reach for g in o.reaches or (o.gap,) * len(o.segments)]
        out = shapely.buffer(np.array(lines, dtype=object), np.array(widths, dtype=np.float64), cap_style="flat")
        return [p for p in out.tolist() if not p.is_empty]
