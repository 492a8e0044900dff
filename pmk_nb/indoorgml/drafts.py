"""The pre-standard IndoorGML drafts 0.8/0.9 (namespace the bare word "indoorCore", schema 0_8_2).

The 2016 archive of the IndoorGML site keeps FJK-Haus in this encoding: a MultiLayeredGraph root,
each cell written as the State's ``duality`` element itself (its own gml:id, gml:name and a
Geometry3D), transitions naming their states with ``start``/``end``. No navi types: every cell is a
space. They are read like 1.0 (not ALMA, whose plain CellSpaces are obstacles).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pmk_nb.indoorgml.gml import local
from pmk_nb.indoorgml.xmlsafe import GML_ID

if TYPE_CHECKING:
    from lxml import etree

    from pmk_nb.indoorgml.records import RawDocument

DRAFT_VERSION = "0.8/0.9 draft"
_GEOMETRY_NAMES = {"geometry3d", "geometry2d"}
_STATE_NAMES = {"state", "node"}


def is_draft(doc: RawDocument) -> bool:
    """A file of the drafts: a namespace that is the bare word "indoorCore" (no URI)."""
    return any(v.strip().lower() == "indoorcore" for v in doc.namespaces.values())


def draft_cell(elem: etree._Element, parent: str) -> bool:
    """A ``duality`` element that is a cell itself (its own gml:id and a Geometry2D/3D inside), in a
    State (``parent``: its parent's lower-case local name). 1.0 points at the cell; ALMA nests one."""
    return parent in _STATE_NAMES and elem.get(GML_ID) is not None and any(local(c) in _GEOMETRY_NAMES for c in elem)
