"""A storey's rooms read from the map's rooms file: which room a pose is in, and room search.

The rooms file (:mod:`pmk_nb.access.sidecar`) is in the map frame, so a chair pose from the
map server's frame is looked up directly. The map grid and the accessibility check of the links
are loaded on first use and cached per chair width (the check labels the whole storey once).
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import shapely

from pmk_nb.access import StoreyPlanFile, check_plan_file, read_sidecar
from pmk_nb.guide.errors import UnknownRoom
from pmk_nb.indoorgml import CellKind
from pmk_nb.rosmap import read_map

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from pmk_nb.access import StoreyReport
    from pmk_nb.grid import OccupancyGrid
    from pmk_nb.indoorgml import Cell
    from pmk_nb.openings import Opening


@dataclass(frozen=True)
class Room:
    """One cell of the storey (a room, corridor, door or obstacle) in the map frame."""

    id: str
    name: str
    kind: CellKind
    polygon: BaseGeometry

    @property
    def label(self) -> str:
        """What the user reads: the name, or the id when the file gives none."""
        return self.name or self.id

    @property
    def is_destination(self) -> bool:
        """A place to go to: free, not a door, and not a doorway drawn as a space (FZK-Haus models its
        doorways as navigable cells 0.24 m deep): doors and doorways are passed through, not visited."""
        return (
            self.kind.is_free
            and not self.kind.is_door
            and not shapely.buffer(self.polygon, -MIN_ROOM_WIDTH / 2).is_empty
        )


#: the narrowest cell offered as a destination (m): thinner cells are doorways or wall niches; a room
#: too small for a wider chair is still offered, and says why when chosen
MIN_ROOM_WIDTH = 0.5


def _norm(text: str) -> str:
    return " ".join(text.casefold().split())


@dataclass
class RoomsMap:
    """The rooms of one map (one storey): the sidecar's cells and openings, the map grid on demand."""

    yaml: Path
    rooms: list[Room]
    plan: StoreyPlanFile  # the rooms file: cells, openings, links left unchecked
    _grid: OccupancyGrid | None = field(default=None, repr=False)
    _reports: dict[float, StoreyReport] = field(default_factory=dict, repr=False)
    _lock: threading.Lock = field(default_factory=threading.Lock, repr=False)

    @property
    def storey(self) -> str:
        return self.plan.storey

    @property
    def cells(self) -> list[Cell]:
        return self.plan.cells

    @property
    def openings(self) -> list[Opening]:
        return self.plan.openings

    # -- lookups -------------------------------------------------------------------------------------
    def by_id(self, room_id: str) -> Room:
        for r in self.rooms:
            if r.id == room_id:
                return r
        raise UnknownRoom(room_id, self.storey)

    def room(self, query: str) -> Room:
        """The room called ``query`` (name or id, case and spacing ignored).

        Raises:
            UnknownRoom: no room has that name or id.
        """
        q = _norm(query)
        for r in self.rooms:
            if _norm(r.name) == q or _norm(r.id) == q:
                return r
        raise UnknownRoom(query, self.storey)

    def destinations(self) -> list[Room]:
        """Rooms one can go to, sorted by name (what the "Go to…" list offers)."""
        return sorted((r for r in self.rooms if r.is_destination), key=lambda r: _norm(r.label))

    def search(self, text: str) -> list[Room]:
        """Destinations whose name holds every word of ``text``: exact names first, then by prefix."""
        words = _norm(text).split()
        found = [r for r in self.destinations() if all(wd in _norm(r.label) for wd in words)]
        q = " ".join(words)
        return sorted(found, key=lambda r: (_norm(r.label) != q, not _norm(r.label).startswith(q), _norm(r.label)))

    def room_at(self, x: float, y: float) -> Room | None:
        """The room the point is in: the smallest free cell holding it (a room drawn inside a hall
        wins over the hall); a door cell only when no room holds it; None off the rooms."""
        holding = [r for r in self.rooms if r.kind.is_free and shapely.intersects_xy(r.polygon, x, y)]
        if not holding:
            return None
        return min(holding, key=lambda r: (r.kind.is_door, r.polygon.area))

    # -- the map and the accessibility rules ---------------------------------------------------------
    @property
    def grid(self) -> OccupancyGrid:
        """The map as a map server publishes it (read once)."""
        with self._lock:
            if self._grid is None:
                self._grid = read_map(self.yaml)
            return self._grid

    def access(self, chair_width: float) -> StoreyReport:
        """The accessibility report of this storey for a chair ``chair_width`` m wide (cached)."""
        key = round(float(chair_width), 3)
        grid = self.grid
        with self._lock:
            report = self._reports.get(key)
        if report is None:
            report = check_plan_file(self.plan, grid, chair_width=key)
            with self._lock:
                self._reports[key] = report
        return report


def load_rooms(yaml_path: str | Path, grid: OccupancyGrid | None = None) -> RoomsMap:
    """The rooms of the map ``yaml_path`` (its ``NAME.rooms.json``); ``grid`` if already loaded.

    Raises:
        MapNotFound: no map at ``yaml_path`` (names the maps in that folder).
        MapFormatError: no rooms file beside the map, or a damaged one (names the file).
    """
    plan = read_sidecar(yaml_path)
    rooms = [Room(c.id, c.name, c.kind, c.footprint) for c in plan.cells]
    return RoomsMap(Path(yaml_path), rooms, plan, grid)
