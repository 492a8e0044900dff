"""Door cells drawn as thin slabs: the two openings through one slab lie on one straight line.

A cell a wall thick (at most :data:`MAX_DEPTH` deep) between two rooms that the graph joins through it
(a transition from each room to the slab, no door geometry) gets an opening on each face. Placed face by
face, each in the middle of its own face, they sat 0.9-2.6 m apart along a 16 m slab, and no chair turns
inside 0.6-0.8 m (issue 37). The two are placed at one position along the slab instead: the middle of
where both faces can hold a door, else the slab's middle, so the chair goes straight through.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
import shapely

from pmk_nb.geometry import door_frame
from pmk_nb.openings.doorslide import place, straight_pieces

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from pmk_nb.indoorgml import Cell
    from pmk_nb.openings.model import Opening

MAX_DEPTH = 1.0  # metres: a cell no deeper than this, and longer than deep, is a slab in a wall
_PLACED = ("line", "middle")  # rules that choose a position on the face (door geometry is kept as given)


def align_slabs(
    openings: list[Opening],
    cells: dict[str, Cell],
    face: Callable[[Opening], Sequence[BaseGeometry]],
    width: float,
    inset: float,
) -> list[Opening]:
    """``openings`` with each slab's two placed openings moved onto one line across it. ``face``: an
    opening's shared boundary as runs (where it may be placed)."""
    by_slab: dict[str, list[int]] = defaultdict(list)
    for i, o in enumerate(openings):
        if o.rule in _PLACED:
            for end in (o.link.a, o.link.b):
                if _is_slab(cells[end]):
                    by_slab[end].append(i)
    out = list(openings)
    for sid, idx in by_slab.items():
        if len(idx) != 2:
            continue  # a slab joining more than two cells is a corridor: its doors stay where they are
        frame = door_frame(cells[sid].footprint)
        if frame is None:
            continue
        centre, across, along = frame
        u = along / float(np.hypot(*along))
        faces = [face(openings[i]) for i in idx]
        if not _opposite(faces, centre, across):
            continue
        t = _common(faces, centre, u, width)
        at = shapely.Point(*(centre + u * t))
        for i, runs in zip(idx, faces, strict=True):
            if runs:
                seg = place(runs, width, inset, shapely.Point(shapely.get_coordinates(_nearest(runs, at))[0]))
                out[i] = replace(openings[i], segments=(seg,), width=seg.length)
    return out


def _is_slab(cell: Cell) -> bool:
    frame = door_frame(cell.footprint)
    if frame is None or not cell.kind.is_free or cell.kind.is_door:
        return False
    depth, length = float(np.hypot(*frame[1])), float(np.hypot(*frame[2]))
    return 0 < depth <= MAX_DEPTH and length >= 1.3 * depth


def _opposite(faces: list[Sequence[BaseGeometry]], centre: np.ndarray, across: np.ndarray) -> bool:
    """The two faces lie on the two sides of the slab (not two rooms along one face)."""
    if not all(faces):
        return False
    sides = [
        float(np.dot(np.mean([shapely.get_coordinates(g.centroid)[0] for g in f], axis=0) - centre, across))
        for f in faces
    ]
    return sides[0] * sides[1] < 0


def _common(faces: list[Sequence[BaseGeometry]], centre: np.ndarray, u: np.ndarray, width: float) -> float:
    """Where along the slab (from its centre, along ``u``) both faces have a straight piece a door wide:
    the middle of the widest such overlap, else 0 (the slab's middle)."""
    spans = []
    for runs in faces:
        pieces = [p for r in runs for p in straight_pieces(r)]
        ts = [sorted(float(np.dot(xy - centre, u)) for xy in shapely.get_coordinates(p)) for p in pieces]
        spans.append([(lo, hi) for lo, *_, hi in ts])
    best = (0.0, 0.0)
    for lo0, hi0 in spans[0]:
        for lo1, hi1 in spans[1]:
            lo, hi = max(lo0, lo1), min(hi0, hi1)
            if hi - lo >= width and hi - lo > best[1] - best[0]:
                best = (lo, hi)
    return (best[0] + best[1]) / 2


def _nearest(runs: Sequence[BaseGeometry], at: shapely.Point) -> BaseGeometry:
    """The point of ``runs`` nearest ``at``: the door's centre line crossing this face."""
    line = min(runs, key=lambda r: r.distance(at))
    return line.interpolate(line.project(at))
