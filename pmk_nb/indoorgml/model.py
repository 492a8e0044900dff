"""The building model every IndoorGML dialect is read into.

All coordinates are metres in the building's own frame (the file's coordinates times the unit
scale); the georeference says how that frame sits in the world.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from pmk_nb.indoorgml.units import UnitSuspect, UnitVote


class CellKind(str, Enum):
    """What a cell is for the wheelchair; decides free/occupied in the grid."""

    NAVIGABLE = "navigable"  # navi:NavigableSpace and plain core:CellSpace in a topographic layer
    GENERAL = "general"  # navi:GeneralSpace (rooms)
    TRANSITION = "transition"  # navi:TransitionSpace (corridors, stairs)
    CONNECTION = "connection"  # navi:ConnectionSpace (doors)
    ANCHOR = "anchor"  # navi:AnchorSpace (entrances)
    NON_NAVIGABLE = "non-navigable"  # NonNavigableSpace (obstacles, columns)

    @property
    def is_free(self) -> bool:
        return self is not CellKind.NON_NAVIGABLE

    @property
    def is_door(self) -> bool:
        return self in (CellKind.CONNECTION, CellKind.ANCHOR)


@dataclass(slots=True)
class Cell:
    id: str
    kind: CellKind
    footprint: BaseGeometry  # shapely Polygon/MultiPolygon in metres (2D)
    storey: str
    name: str = ""
    layer: str = ""
    z_min: float | None = None
    z_max: float | None = None
    boundary_ids: list[str] = field(default_factory=list)
    # judged a window or sill from its floor height, not declared so by the file: the reader's rule
    # may misjudge a door on a sloping floor, so the check names the transitions this leaves out
    window: bool = False


@dataclass(slots=True)
class Boundary:
    """A CellSpaceBoundary; doors let the rasteriser open the wall they sit in."""

    id: str
    is_door: bool
    geometry: BaseGeometry | None  # 2D LineString/Polygon footprint in metres, or None
    storey: str | None = None
    name: str = ""
    virtual: bool = False  # a boundary with no wall (isVirtual), e.g. between pieces of one corridor
    evidence: str = ""  # why it is a door: type / name / partial (edge) / duality (a transition's face)


@dataclass
class State:
    id: str
    point: tuple[float, float, float] | None
    cell_id: str | None
    layer: str = ""


@dataclass(slots=True)
class Transition:
    id: str
    source: str
    target: str
    weight: float | None = None
    layer: str = ""
    line: BaseGeometry | None = None  # its own 2D LineString in metres, when the file gives one


@dataclass(frozen=True)
class Link:
    """A transition resolved to the two cells it joins: the graph's word that a chair may pass."""

    id: str  # the transition's id
    a: str  # cell ids
    b: str
    line: BaseGeometry | None = None
    storeys: tuple[str, str] = ("", "")

    @property
    def same_storey(self) -> bool:
        return self.storeys[0] == self.storeys[1]


@dataclass
class NavGraph:
    states: dict[str, State] = field(default_factory=dict)
    transitions: list[Transition] = field(default_factory=list)


@dataclass
class Storey:
    name: str
    elevation: float | None  # floor z in metres, when known
    cell_ids: list[str] = field(default_factory=list)
    source: str = ""  # how the storey was found: level / description / extension / z / single


@dataclass
class Georeference:
    translation: tuple[float, float] = (0.0, 0.0)  # metres, building frame -> world
    rotation: float = 0.0  # degrees, counter-clockwise
    lla: tuple[float, float, float] | None = None  # lat, lon, alt of the frame origin
    srs_name: str | None = None  # the CRS of the file's coordinates (its srsName, or --crs); None: a local frame
    # where the building frame's (0, 0) lies in that CRS, metres: large projected coordinates (UTM, Web
    # Mercator) are read relative to this local origin (see indoorgml.crs)
    origin: tuple[float, float] = (0.0, 0.0)


@dataclass(frozen=True)
class LayerNote:
    """A space layer of the file that is not drawn, and why (shown by ``pmk info`` and ``pmk convert``)."""

    id: str
    cells: int  # its cells with a footprint
    reason: str
    name: str = ""
    obstacles: int = 0  # its non-navigable cells inside the drawn floor, drawn as obstacles all the same


LOST_SHARE = 0.9  # a graph whose transitions are this share dangling (or none resolved) is lost


@dataclass(frozen=True)
class GraphStatus:
    """How much of the file's navigation graph could be used: the access check trusts only what resolved.

    ``resolved``: transitions whose two ends name cells of the plan (directly, through their states'
    duality, or a state's point); ``dangling``: transitions with an end naming nothing in the file."""

    transitions: int = 0
    resolved: int = 0
    dangling: int = 0
    absent: bool = True
    reason: str = ""

    @property
    def lost(self) -> bool:
        """No graph, or one that joins (nearly) nothing: nothing can be checked against it."""
        return self.absent or self.resolved == 0 or self.dangling >= LOST_SHARE * self.transitions

    def to_json(self) -> dict[str, object]:
        return {
            "transitions": self.transitions,
            "resolved": self.resolved,
            "dangling": self.dangling,
            "absent": self.absent,
            "lost": self.lost,
            "reason": self.reason,
        }


@dataclass(frozen=True)
class CellOverlap:
    """Two cells of one storey whose plans overlap (``pmk info`` names each pair; ``overlaps`` finds them)."""

    storey: str
    a: str  # cell ids, in the order the storey lists them
    b: str
    area: float  # m² the two share
    share: float  # of the smaller cell's area, 0-1


@dataclass
class Building:
    source: str  # path of the file read
    sha256: str
    version: str  # "1.0", "1.0.3", "1.1", "2.0", "alma", ...
    namespaces: dict[str, str]  # prefix -> URI as declared
    unit: str  # "m" | "cm" | "mm"
    unit_reason: str
    storeys: list[Storey]
    cells: dict[str, Cell]
    boundaries: dict[str, Boundary] = field(default_factory=dict)
    graph: NavGraph = field(default_factory=NavGraph)
    georef: Georeference = field(default_factory=Georeference)
    layers: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    links: list[Link] = field(default_factory=list)  # transitions between kept cells, one per pair
    unit_conflict: str = ""  # plain words when the unit evidence disagrees ('' when it agrees)
    skipped_layers: list[LayerNote] = field(default_factory=list)  # layers of the file not drawn, and why
    graph_status: GraphStatus = field(default_factory=GraphStatus)
    unit_suspect: UnitSuspect | None = None  # the unit, not the doors, is the likely fault (a unit given by hand)
    unit_votes: list[UnitVote] = field(default_factory=list)  # each piece of unit evidence and the unit it says
    overlaps: list[CellOverlap] = field(default_factory=list)  # cells of one storey that overlap, largest first
    _by_storey: tuple[tuple[int, int], dict[str | None, list[Boundary]]] | None = field(
        default=None, init=False, repr=False, compare=False
    )

    def storey(self, name: str) -> Storey:
        for s in self.storeys:
            if s.name == name:
                return s
        known = ", ".join(s.name for s in self.storeys)
        from pmk_nb.errors import IndoorGMLError

        raise IndoorGMLError(
            f"{self.source}: no storey named {name!r}; storeys are: {known}", path=self.source, element=name
        )

    def cells_of(self, storey: str) -> list[Cell]:
        return [self.cells[c] for c in self.storey(storey).cell_ids]

    def links_of(self, storey: str) -> list[Link]:
        """Links between two cells of ``storey`` (stairs and lifts to other storeys excluded)."""
        return [k for k in self.links if k.storeys == (storey, storey)]

    def doors_of(self, storey: str) -> list[Boundary]:
        return [b for b in self.boundaries_of(storey) if b.is_door]

    def boundaries_of(self, storey: str) -> list[Boundary]:
        """The boundaries of ``storey``, in file order. Indexed once per set of boundaries: a storey
        at a time, a scan of all of them made converting N storeys cost N x (all boundaries)."""
        key = (id(self.boundaries), len(self.boundaries))
        if self._by_storey is None or self._by_storey[0] != key:
            index: dict[str | None, list[Boundary]] = {}
            for b in self.boundaries.values():
                index.setdefault(b.storey, []).append(b)
            self._by_storey = (key, index)
        return list(self._by_storey[1].get(storey, []))
