"""What the maps list tells about a source before it is converted: its storeys, cells, doors, size.

Reading an IndoorGML file can take seconds for a large building, so the result is cached per source
file, keyed by path + mtime_ns + size: an edited or replaced file is read again. The cache lives in
memory on one :class:`~pmk_nb.library.folder.MapsFolder` only (no sidecar file): the folder keeps the
original ALMA_MAPS contract that every file in it is a source or a generated map, and that a failed
action leaves it exactly as it was.
"""

from __future__ import annotations

import os
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pmk_nb.errors import IndoorGMLError, LibraryError

if TYPE_CHECKING:
    from pmk_nb.indoorgml import Building

__all__ = ["LayerOption", "StoreyCache", "StoreyInfo", "layer_options", "plan_notes", "storeys_of"]

_Key = tuple[int, int]  # (mtime_ns, size) of the source when it was read


@dataclass(frozen=True)
class StoreyInfo:
    """One storey of a building as the maps list shows it.

    ``extent`` is ``(min_x, min_y, max_x, max_y)`` in metres, None for a storey without cells.
    """

    name: str
    cells: int
    doors: int
    extent: tuple[float, float, float, float] | None
    unit_conflict: str = ""  # the building's unit evidence disagrees (said before converting), with the fix
    unit: str = "m"  # the unit the file was read in (judged from its sizes): what ``extent`` was scaled by
    notes: tuple[str, ...] = ()  # the plan's doubts, said before converting (see plan_notes)
    layers: tuple[LayerOption, ...] = ()  # the space layers with cells: what the Maps screen offers to draw
    origin: tuple[float, float] = (0.0, 0.0)  # where ``extent``'s (0, 0) lies in the plan's CRS (local origin)

    @property
    def size(self) -> tuple[float, float] | None:
        """Width and height in metres."""
        if self.extent is None:
            return None
        return (self.extent[2] - self.extent[0], self.extent[3] - self.extent[1])

    def size_as(self, unit: str) -> tuple[float, float] | None:
        """Width and height in metres were the file read in ``unit`` ("auto": as it was read)."""
        from pmk_nb.indoorgml import UNIT_SCALE

        size = self.size
        if size is None or unit not in UNIT_SCALE or unit == self.unit:
            return size
        k = UNIT_SCALE[unit] / UNIT_SCALE[self.unit]
        return (size[0] * k, size[1] * k)

    def describe(self) -> str:
        """``F1: 15 cells, 6 doors, 30.0 × 15.0 m`` for lists and logs."""
        size = self.size
        dims = f"{size[0]:.1f} × {size[1]:.1f} m" if size else "no extent"
        return f"{self.name}: {self.cells} cells, {self.doors} doors, {dims}"


@dataclass(frozen=True)
class LayerOption:
    """A space layer with cells, and whether the converter draws it when nothing is asked (the navigable one)."""

    id: str
    name: str
    cells: int
    drawn: bool
    reason: str = ""  # why it is not drawn


def plan_notes(building: Building) -> tuple[str, ...]:
    """What a user must know before trusting a map of ``building``, in plain words: the unit suspected
    first (it makes every door wrong), then a navigation graph lost or partly dangling (nothing, or less,
    can be checked), then each layer with cells not drawn and why (a layer of states alone draws nothing)."""
    notes = [building.unit_suspect.message] if building.unit_suspect is not None else []
    graph = building.graph_status
    if graph.lost:
        notes.append(graph.reason or "the file has no navigation graph: nothing can be checked")
    elif graph.dangling:
        notes.append(graph.reason or f"{graph.dangling} of {graph.transitions} transitions name nothing in the file")
    notes += [f"Layer {n.id!r} ({n.cells} cells) not drawn: {n.reason}" for n in building.skipped_layers if n.cells]
    return tuple(notes)


def layer_options(building: Building) -> tuple[LayerOption, ...]:
    """The layers drawn (those of the building's cells) and the ones with cells left out, in file order."""
    drawn = {c.layer for c in building.cells.values()}
    skipped = {n.id: n for n in building.skipped_layers if n.cells}
    out = []
    for lid in building.layers:
        if lid in skipped:
            n = skipped[lid]
            out.append(LayerOption(lid, n.name, n.cells, False, n.reason))
        elif lid in drawn:
            count = sum(1 for c in building.cells.values() if c.layer == lid)
            out.append(LayerOption(lid, "", count, True))
    return tuple(out)


def storeys_of(building: Building) -> list[StoreyInfo]:
    """The storeys of a read building, via ``summarize`` (the same numbers as ``pmk info``)."""
    from pmk_nb.indoorgml import summarize

    result = []
    notes, layers = plan_notes(building), layer_options(building)
    for st in summarize(building)["storeys"]:
        ext: dict[str, Any] | None = st["extent"]
        extent = (*map(float, ext["min"]), *map(float, ext["max"])) if ext else None
        result.append(
            StoreyInfo(
                name=str(st["name"]),
                cells=int(st["cells"]),
                doors=int(st["doors"]),
                extent=extent,  # type: ignore[arg-type]
                unit_conflict=building.unit_conflict,
                unit=building.unit,
                notes=notes,
                layers=layers,
                origin=building.georef.origin,
            )
        )
    return result


def _key(path: Path) -> _Key:
    st = os.stat(path)
    return (st.st_mtime_ns, st.st_size)


class StoreyCache:
    """Storeys per source file, valid while the file's mtime and size are unchanged.

    Thread-safe: the Maps screen reads storeys in a background thread while the list is refreshed.
    ``reads`` counts the files actually parsed (tests and logs use it to see cache hits).
    """

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._entries: dict[Path, tuple[_Key, list[StoreyInfo]]] = {}
        self.reads = 0

    def cached(self, path: Path) -> list[StoreyInfo] | None:
        """The storeys if known for the file as it is now, else None; never reads the file."""
        try:
            key = _key(path)
        except OSError:
            return None
        with self._lock:
            hit = self._entries.get(path)
        return list(hit[1]) if hit is not None and hit[0] == key else None

    def put(self, path: Path, key: _Key, building: Building) -> list[StoreyInfo]:
        """Remember the storeys of ``building`` read from ``path`` when it had ``key``."""
        info = storeys_of(building)
        with self._lock:
            self._entries[path] = (key, info)
        return list(info)

    def get(self, path: Path, label: str) -> list[StoreyInfo]:
        """The storeys of ``path``, read (and cached) if not known for its current mtime and size.

        Raises:
            LibraryError: the file is missing, unreadable or not valid IndoorGML (the message names
                the map ``label`` and the file and chains the reader's error).
        """
        try:
            key = _key(path)
        except OSError as err:
            raise LibraryError(f"cannot read the storeys of map {label!r}: {path}: {err.strerror or err}") from err
        with self._lock:
            hit = self._entries.get(path)
        if hit is not None and hit[0] == key:
            return list(hit[1])
        from pmk_nb.indoorgml import read_building

        try:
            building = read_building(path)
        except IndoorGMLError as err:
            raise LibraryError(f"cannot read the storeys of map {label!r} ({path.name}): {err}") from err
        except OSError as err:
            raise LibraryError(f"cannot read the storeys of map {label!r}: {path}: {err.strerror or err}") from err
        with self._lock:
            self.reads += 1
        return self.put(path, key, building)

    def forget(self, path: Path) -> None:
        with self._lock:
            self._entries.pop(path, None)
