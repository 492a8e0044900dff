"""The raw records of an IndoorGML document: what ``scan`` read, in file units, not interpreted yet.

Apart from the scanner so that the modules that read a draft's or a dialect's details (``drafts``)
can name a document without importing the scanner that calls them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from pmk_nb.indoorgml.gml import Coord, PolygonZ, RingStats


@dataclass(slots=True)
class RawCell:
    id: str
    kind_name: str  # lower-cased local name of the element
    name: str
    description: str
    polygons: list[PolygonZ]
    line: int | None
    layer: str = ""
    storey_hint: str | None = None
    storey_source: str = ""
    duality: str | None = None
    boundary_refs: list[str] = field(default_factory=list)
    wrapped: bool = False  # geometry inside cellSpaceGeometry (1.0.1+)
    alma_inline: bool = False  # cell written inside State/duality (ALMA MultiLayeredGraph)


@dataclass(slots=True)
class RawBoundary:
    id: str
    kind_name: str
    name: str
    description: str
    polygons: list[PolygonZ]
    lines: list[list[Coord]]
    duality: str | None
    line: int | None
    virtual: bool = False  # IndoorGML 2.0 isVirtual, or a name/description saying "virtual"


@dataclass(slots=True)
class RawState:
    id: str
    point: Coord | None
    cell: str | None
    layer: str


@dataclass(slots=True)
class RawTransition:
    id: str
    connects: list[str]
    weight: float | None
    duality: str | None
    layer: str
    line: list[Coord] | None = None  # the transition's own geometry (a LineString), file units


@dataclass
class RawLayer:
    id: str
    cls: str = ""
    usage: str = ""
    function: str = ""
    name: str = ""
    kind_name: str = ""  # spacelayer (1.x), primalspacelayer / dualspacelayer / thematiclayer (2.0)
    theme: str = ""  # 2.0 ThematicLayer theme: Physical, Virtual, Tangible, Unknown
    semantic_extension: bool = False  # 2.0 ThematicLayer semanticExtension
    parent: str = ""  # 2.0: the ThematicLayer a primal/dual layer sits in


@dataclass
class RawDocument:
    path: Path
    root: str
    namespaces: dict[str, str]
    cells: list[RawCell] = field(default_factory=list)
    boundaries: list[RawBoundary] = field(default_factory=list)
    states: list[RawState] = field(default_factory=list)
    transitions: list[RawTransition] = field(default_factory=list)
    layers: list[RawLayer] = field(default_factory=list)
    translation: tuple[float, float] | None = None
    rotation: float | None = None
    lla: tuple[float, float, float] | None = None
    srs_name: str | None = None
    has_level: bool = False
    has_primal_layer: bool = False
    stats: RingStats = field(default_factory=RingStats)
