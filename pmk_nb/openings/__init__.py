"""The openings plan: where the navigation graph says a chair may pass, and where in the wall each
opening goes (door geometry, the transition's line, corridor, middle of the wall, a bridge across a
missing landing), plus the door lines the graph keeps shut and the seams between cells it does not join.

The rasteriser draws the plan (``raster``), the accessibility check measures it (``access``), the
guide routes over it (``guide``). Read top to bottom: ``model`` (what a plan holds: openings, skipped
links), ``plan`` (the rules, :func:`plan_openings`), ``doorface`` (an askew door cell's face),
``doorslide`` (a door without geometry on one straight stretch, clear of corners), ``outside``
(guessed doors on outer walls stay wall), ``thickness`` (gaps are wall up to the thickest wall the
file's openings cross), ``slab`` (doors through a thin cell in a wall, aligned), ``nearby`` (R-trees:
what lies near a link).
"""

from __future__ import annotations

from pmk_nb.openings.model import SKIP_DECLARED, SKIP_WINDOW, Opening, OpeningPlan, Skipped
from pmk_nb.openings.outside import facing_outside
from pmk_nb.openings.plan import plan_openings
from pmk_nb.openings.thickness import thickest_wall

__all__ = [
    "SKIP_DECLARED",
    "SKIP_WINDOW",
    "Opening",
    "OpeningPlan",
    "Skipped",
    "facing_outside",
    "plan_openings",
    "thickest_wall",
]
