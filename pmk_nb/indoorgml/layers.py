"""Which cells a building is made of: those with a footprint, from the layer(s) that hold the geometry.

Files often carry several SpaceLayers describing the same space (a topographic layer plus a
navigation layer subdividing it); counting both would double every room, so only the geometry
layer(s) are kept (ALMA style: layer ``L1`` or the TOPOGRAPHIC/geometry one).
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass

from pmk_nb.errors import IndoorGMLError
from pmk_nb.indoorgml import doors as doorlib
from pmk_nb.indoorgml.footprint import Footprint, cell_footprints
from pmk_nb.indoorgml.scan import RawCell, RawDocument

GEOMETRY_LAYER_WORDS = ("base", "primal", "topographic", "geometry", "physical")


@dataclass
class KeptCell:
    """A cell with a usable footprint (file units) and the layer it belongs to."""

    raw: RawCell
    fp: Footprint
    layer: str


def _cell_layers(doc: RawDocument) -> dict[str, str]:
    """Layer of each cell: the SpaceLayer it sits in, else the layer of its dual State."""
    state_layer = {s.id: s.layer for s in doc.states}
    layer_of: dict[str, str] = {}
    for s in doc.states:
        if s.cell and s.layer:
            layer_of.setdefault(s.cell, s.layer)
    for c in doc.cells:
        if c.layer:
            layer_of[c.id] = c.layer
        elif c.id not in layer_of and c.duality in state_layer:
            layer_of[c.id] = state_layer[c.duality]
    return layer_of


def select_layers(cells: list[KeptCell], doc: RawDocument, alma: str, warnings: list[str]) -> list[KeptCell]:
    """Keep the geometry layer(s); drop layers that only repeat/subdivide the same space."""
    by_layer: dict[str, list[KeptCell]] = defaultdict(list)
    for c in cells:
        by_layer[c.layer].append(c)
    order = [layer.id for layer in doc.layers if layer.id in by_layer]
    if len(order) <= 1:
        return cells
    info = {layer.id: layer for layer in doc.layers}
    if alma:
        geo = [
            lid for lid in order
            if lid == "L1" or (info[lid].cls.upper() == "TOPOGRAPHIC" and info[lid].usage.lower() == "geometry")
        ]  # fmt: skip
        keep = geo[:1] or order[:1]
        dropped = [lid for lid in order if lid not in keep]
        warnings.append(f"ALMA style: geometry from layer {keep[0]!r} only; ignored layers {dropped}")
        return [c for c in cells if c.layer in keep or c.layer == ""]

    def rank(lid: str) -> int:
        text = f"{lid} {info[lid].cls} {info[lid].usage}".lower()
        return 0 if any(w in text for w in GEOMETRY_LAYER_WORDS) else 1

    primary = min(order, key=lambda lid: (rank(lid), order.index(lid)))
    kept = {primary, ""}
    base = [c.fp.geometry for c in by_layer[primary] + by_layer.get("", []) if c.fp.geometry is not None]
    for lid in order:
        if lid == primary:
            continue
        geoms = [c.fp.geometry for c in by_layer[lid] if c.fp.geometry is not None]
        share = doorlib.overlap_fraction(geoms, base)
        if share > 0.5:
            warnings.append(
                f"layer {lid!r}: {len(by_layer[lid])} cells lie inside layer {primary!r} "
                f"({share:.0%} overlap) - ignored to avoid double-counting; geometry from {primary!r}"
            )
        else:
            kept.add(lid)
            base.extend(geoms)
    return [c for c in cells if c.layer in kept]


def usable_cells(doc: RawDocument, warnings: list[str]) -> list[KeptCell]:
    """Cells with a non-empty footprint (repaired if needed), each with its layer."""
    layer_of = _cell_layers(doc)
    cells: list[KeptCell] = []
    drawn = [raw for raw in doc.cells if raw.polygons]
    no_geom = len(doc.cells) - len(drawn)
    for raw, fp in zip(drawn, cell_footprints([raw.polygons for raw in drawn]), strict=True):
        if fp.geometry is None:
            warnings.append(f"cell {raw.id!r} (line {raw.line}): zero-area footprint - skipped")
            continue
        if fp.repaired:
            warnings.append(f"cell {raw.id!r} (line {raw.line}): invalid/self-intersecting polygon repaired")
        cells.append(KeptCell(raw, fp, layer_of.get(raw.id, "")))
    if no_geom:
        warnings.append(f"{no_geom} cells have no geometry (skipped)")
    if not cells:
        graph_only = not doc.cells and (doc.states or doc.transitions)
        raise IndoorGMLError(
            f"{doc.path}: no usable cell: {len(doc.cells)} cell elements, none with a non-empty 2D/3D geometry"
            + (f"; the file holds only a navigation graph ({len(doc.states)} states, "
               f"{len(doc.transitions)} transitions)" if graph_only else ""),
            path=str(doc.path), element="CellSpace",
            hint="A map is drawn from the cells' shapes: export the building with its CellSpace geometry "
            "(Geometry2D or Geometry3D) as well as the graph.",
        )  # fmt: skip
    return cells
