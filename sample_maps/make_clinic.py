"""Generate the ALMA-style sample buildings in this folder (reproducible, no randomness).

Run: ``.venv/bin/python sample_maps/make_clinic.py`` -> clinic_floor.gml, clinic_two_storeys.gml

The files mimic what the ALMA servers served to the original app: ``indoorCore:``/``indoorNavi:``
prefixes on the IndoorGML 1.0 namespaces, a ``MultiLayeredGraph`` root, CellSpaces inline in
``State/duality``, layer L1 (class TOPOGRAPHIC, usage Geometry) holding the geometry, 2D
``gml:posList`` rings in centimetres, and the map frame as ``indoorNavi:translation`` /
``indoorNavi:rotation``. Layout (metres, building frame) - see README.md for the table.
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

from lxml import etree

GML = "http://www.opengis.net/gml/3.2"
CORE = "http://www.opengis.net/indoorgml/1.0/core"
NAVI = "http://www.opengis.net/indoorgml/1.0/navigation"
XLINK = "http://www.w3.org/1999/xlink"
NSMAP = {"gml": GML, "indoorCore": CORE, "indoorNavi": NAVI, "xlink": XLINK}

WALL = 20  # cm between rooms and the corridor; doors (ConnectionSpace) span this gap
DOOR = 90  # cm door width
TRANSLATION_CM = (250000.0, 120000.0)  # map frame origin in the world, centimetres
ROTATION_DEG = 30.0


@dataclass(frozen=True)
class Space:
    id: str
    name: str
    kind: str  # indoorNavi local name
    box: tuple[float, float, float, float]  # x0, y0, x1, y1 in cm


def clinic_spaces(suffix: str = "", *, upper: bool = False) -> list[Space]:
    """One clinic floor 30 m x 15 m: corridor y 6.1-8.9 m, three rooms on each side.

    The upper floor (``upper=True``) has a bed in exam room 1 instead of the reception desk.
    """
    s = suffix
    south, north = (0.0, 590.0), (910.0, 1500.0)
    corridor = (610.0, 890.0)
    rooms = [
        ("R1", "Waiting room", 0, 1000, south, 450),
        ("R2", "Exam room 1", 1000, 2000, south, 1450),
        ("R3", "Exam room 2", 2000, 3000, south, 2450),
        ("R4", "Office", 0, 1200, north, 550),
        ("R5", "Treatment room", 1200, 2000, north, 1550),
        ("R6", "Storage", 2000, 3000, north, 2450),
    ]
    out = [Space(f"COR{s}", "Corridor", "NavigableSpace", (0.0, corridor[0], 3000.0, corridor[1]))]
    for rid, name, x0, x1, (y0, y1), door_x in rooms:
        out.append(Space(f"{rid}{s}", name, "NavigableSpace", (x0, y0, x1, y1)))
        gap = (y1, corridor[0]) if y0 == 0.0 else (corridor[1], y0)
        out.append(Space(f"D{rid[1:]}{s}", f"Door {name}", "ConnectionSpace", (door_x, gap[0], door_x + DOOR, gap[1])))
    if upper:
        out.append(Space(f"BED{s}", "Bed", "NonNavigableSpace", (1200.0, 100.0, 1300.0, 300.0)))
    else:
        out.append(Space(f"DESK{s}", "Reception desk", "NonNavigableSpace", (300.0, 350.0, 700.0, 450.0)))
    out.append(Space(f"PIL{s}", "Pillar", "NonNavigableSpace", (200.0, 1200.0, 260.0, 1260.0)))
    return out


def _poslist(box: tuple[float, float, float, float]) -> str:
    x0, y0, x1, y1 = box
    ring = [(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)]
    return " ".join(f"{x:.1f} {y:.1f}" for x, y in ring)


def _q(ns: str, name: str) -> str:
    return f"{{{ns}}}{name}"


def _state(parent: etree._Element, sp: Space, storey: str | None) -> None:
    member = etree.SubElement(parent, _q(CORE, "stateMember"))
    state = etree.SubElement(member, _q(CORE, "State"), {_q(GML, "id"): f"S_{sp.id}"})
    etree.SubElement(state, _q(GML, "name")).text = sp.name
    dual = etree.SubElement(state, _q(CORE, "duality"))
    cell = etree.SubElement(dual, _q(NAVI, sp.kind), {_q(GML, "id"): sp.id})
    if storey:
        etree.SubElement(cell, _q(GML, "description")).text = f'storey="{storey}":'
    etree.SubElement(cell, _q(GML, "name")).text = sp.name
    geom = etree.SubElement(cell, _q(CORE, "Geometry2D"))
    poly = etree.SubElement(geom, _q(GML, "Polygon"), {_q(GML, "id"): f"G_{sp.id}"})
    ring = etree.SubElement(etree.SubElement(poly, _q(GML, "exterior")), _q(GML, "LinearRing"))
    etree.SubElement(ring, _q(GML, "posList")).text = _poslist(sp.box)
    x0, y0, x1, y1 = sp.box
    point = etree.SubElement(
        etree.SubElement(state, _q(CORE, "geometry")),
        _q(GML, "Point"),
        {_q(GML, "id"): f"P_{sp.id}", "srsDimension": "2"},
    )
    etree.SubElement(point, _q(GML, "pos")).text = f"{(x0 + x1) / 2:.1f} {(y0 + y1) / 2:.1f}"


def _transition(parent: etree._Element, a: str, b: str) -> None:
    member = etree.SubElement(parent, _q(CORE, "transitionMember"))
    t = etree.SubElement(member, _q(CORE, "Transition"), {_q(GML, "id"): f"T_{a}_{b}"})
    etree.SubElement(t, _q(CORE, "weight")).text = "1.0"
    for s in (a, b):
        etree.SubElement(t, _q(CORE, "connects"), {_q(XLINK, "href"): f"#S_{s}"})


def build_document(storeys: list[str | None]) -> etree._ElementTree:
    """The MultiLayeredGraph: L1 geometry (all storeys) + L2 navigation layer without geometry."""
    root = etree.Element(_q(CORE, "MultiLayeredGraph"), {_q(GML, "id"): "CLINIC"}, nsmap=NSMAP)
    meta = etree.SubElement(etree.SubElement(root, _q(GML, "metaDataProperty")), _q(GML, "GenericMetaData"))
    etree.SubElement(meta, _q(NAVI, "translation")).text = f"{TRANSLATION_CM[0]:.1f} {TRANSLATION_CM[1]:.1f}"
    etree.SubElement(meta, _q(NAVI, "rotation")).text = f"{ROTATION_DEG:.1f}"
    layers = etree.SubElement(root, _q(CORE, "spaceLayers"), {_q(GML, "id"): "SLs"})
    l1 = etree.SubElement(
        etree.SubElement(layers, _q(CORE, "spaceLayerMember")), _q(CORE, "SpaceLayer"), {_q(GML, "id"): "L1"}
    )
    etree.SubElement(l1, _q(CORE, "usage")).text = "Geometry"
    etree.SubElement(l1, _q(CORE, "class")).text = "TOPOGRAPHIC"
    nodes = etree.SubElement(l1, _q(CORE, "nodes"), {_q(GML, "id"): "N_L1"})
    edges = etree.SubElement(l1, _q(CORE, "edges"), {_q(GML, "id"): "E_L1"})
    for storey in storeys:
        suffix = f"_{storey}" if len(storeys) > 1 else ""
        spaces = clinic_spaces(suffix, upper=storey not in (None, storeys[0]))
        for sp in spaces:
            _state(nodes, sp, storey)
        for sp in spaces:
            if sp.kind == "ConnectionSpace":
                room = "R" + sp.id[1:]
                _transition(edges, room, sp.id)
                _transition(edges, sp.id, f"COR{suffix}")
    l2 = etree.SubElement(
        etree.SubElement(layers, _q(CORE, "spaceLayerMember")), _q(CORE, "SpaceLayer"), {_q(GML, "id"): "L2"}
    )
    etree.SubElement(l2, _q(CORE, "usage")).text = "Navigation"
    etree.SubElement(l2, _q(CORE, "class")).text = "TOPOGRAPHIC"
    nodes2 = etree.SubElement(l2, _q(CORE, "nodes"), {_q(GML, "id"): "N_L2"})
    member = etree.SubElement(nodes2, _q(CORE, "stateMember"))
    st = etree.SubElement(member, _q(CORE, "State"), {_q(GML, "id"): "NAV_ENTRANCE"})
    etree.SubElement(st, _q(GML, "name")).text = "Entrance"
    first = f"COR_{storeys[0]}" if len(storeys) > 1 else "COR"
    etree.SubElement(st, _q(CORE, "duality"), {_q(XLINK, "href"): f"#{first}"})
    etree.SubElement(l2, _q(CORE, "edges"), {_q(GML, "id"): "E_L2"})
    return etree.ElementTree(root)


def write_atomic(tree: etree._ElementTree, path: Path) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            tree.write(fh, xml_declaration=True, encoding="UTF-8", pretty_print=True)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def main(directory: Path | None = None) -> list[Path]:
    here = directory or Path(__file__).resolve().parent
    outputs = [(here / "clinic_floor.gml", [None]), (here / "clinic_two_storeys.gml", ["F1", "F2"])]
    for path, storeys in outputs:
        write_atomic(build_document(storeys), path)
    return [p for p, _ in outputs]


if __name__ == "__main__":
    for p in main():
        print(p)
