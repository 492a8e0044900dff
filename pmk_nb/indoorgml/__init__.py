"""IndoorGML reader: every dialect seen in the wild -> one :class:`Building` model in metres.

``read_building(path, unit="auto", progress=None)`` and ``summarize(building)`` are the API; the
modules underneath are layered: ``xmlsafe`` (safe streaming XML) -> ``gml`` (coordinates) ->
``records``/``scan`` (raw records) -> ``footprint``/``layers``/``doors``/``units``/``storeys`` -> ``build`` (the model).
"""

from __future__ import annotations

from pmk_nb.errors import IndoorGMLError
from pmk_nb.indoorgml.doors import says_corridor
from pmk_nb.indoorgml.levels import RAISED
from pmk_nb.indoorgml.model import Boundary, Building, Cell, CellKind, CellOverlap, Georeference, Link, Storey
from pmk_nb.indoorgml.reader import read_building
from pmk_nb.indoorgml.sniff import check_indoorgml
from pmk_nb.indoorgml.summary import format_summary, graph_lines, layer_lines, overlap_lines, summarize
from pmk_nb.indoorgml.units import UNIT_CHOICES, UNIT_SCALE, UnitSuspect

__all__ = [
    "RAISED",
    "UNIT_CHOICES",
    "UNIT_SCALE",
    "Boundary",
    "Building",
    "Cell",
    "CellKind",
    "CellOverlap",
    "Georeference",
    "IndoorGMLError",
    "Link",
    "Storey",
    "UnitSuspect",
    "check_indoorgml",
    "format_summary",
    "graph_lines",
    "layer_lines",
    "overlap_lines",
    "read_building",
    "says_corridor",
    "summarize",
]
