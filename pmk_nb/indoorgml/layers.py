"""Which cells a building is made of: those with a footprint, from the navigable layer only.

Files carry several space layers: the navigable primal space, and thematic ones (light zones, sensor or
Wi-Fi coverage, installations) whose cells overlap the rooms and reach outside the building, or a
layer subdividing the rooms. Drawn, a thematic layer's cells would be floor outside and its outlines
walls across rooms; a subdivision would double every room. The navigable layer is the one whose cells
the navigation graph connects; the layers' own words (1.x class/usage/function, 2.0 ThematicLayer
theme) and how their cells lie over the drawn rooms decide the rest. Every layer not drawn gets a
:class:`~pmk_nb.indoorgml.model.LayerNote`; ``--layer`` draws others on request. ALMA style: layer
``L1`` or the TOPOGRAPHIC/geometry one.
"""

from __future__ import annotations

import re
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pmk_nb.errors import IndoorGMLError, UnknownLayer
from pmk_nb.indoorgml.footprint import Footprint, cell_footprints
from pmk_nb.indoorgml.graph import linked_pairs
from pmk_nb.indoorgml.model import LayerNote
from pmk_nb.indoorgml.records import RawCell, RawDocument, RawLayer

GEOMETRY_LAYER_WORDS = ("base", "primal", "topographic", "geometry", "physical", "navigab", "navigation")
# words of a layer that models a theme over the space, not the space itself (light zones, sensor or Wi-Fi
# coverage, installations); 1.x SpaceLayer class SENSOR/LOGICAL/TAGGED; 2.0 ThematicLayer theme other than Physical
THEMATIC_WORDS = re.compile(
    r"\b(?:thematic|sensors?|wi-?fi|wlan|bluetooth|beacons?|rfid|coverage|light(?:s|ing)?|lamps?|installations?|"
    r"hvac|electric(?:al|ity)?|cameras?|cctv|security|safety|landmarks?|virtual)\b"
)
THEMATIC_CLASSES = ("SENSOR", "LOGICAL", "TAGGED")
OBSTACLE_NAMES = ("nonnavigablespace", "obstacle")  # NonNavigableSpace: occupied wherever it is written


@dataclass
class KeptCell:
    """A cell with a usable footprint (file units) and the layer it belongs to."""

    raw: RawCell
    fp: Footprint
    layer: str

    @property
    def geometry(self) -> BaseGeometry:
        """The footprint's plan: never None for a kept cell (cells without one are dropped)."""
        geom = self.fp.geometry
        assert geom is not None, self.raw.id
        return geom


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


def _words(layer: RawLayer, info: dict[str, RawLayer]) -> tuple[bool, str]:
    """What the layer's own words say: (names the physical/navigable space?, why it is thematic or '').
    A 2.0 primal layer speaks through the ThematicLayer it sits in as well."""
    fields = [layer] + ([info[layer.parent]] if layer.parent in info else [])
    theme = next((f.theme for f in fields if f.theme), "")  # Physical, Virtual, Tags, Unknown or "other: ..."
    if theme.lower() == "physical" or any(w in theme.lower() for w in GEOMETRY_LAYER_WORDS[1:]):
        return True, ""
    if theme and theme.lower() != "unknown":
        return False, f"theme {theme}"
    cls = next((f.cls for f in fields if f.cls), "")
    if cls.upper() in THEMATIC_CLASSES:
        return False, f"class {cls}"
    m = THEMATIC_WORDS.search(" ".join(f"{f.id} {f.name} {f.usage} {f.function}" for f in fields).lower())
    if m:
        return False, f"{m.group(0)!r} in its name, usage or function"
    text = " ".join(f"{f.id} {f.name} {f.cls} {f.usage} {f.function}" for f in fields).lower()
    return any(w in text for w in GEOMETRY_LAYER_WORDS), ""


def _no_cells(doc: RawDocument, by_layer: dict[str, list[KeptCell]]) -> list[LayerNote]:
    """Space layers (1.x SpaceLayer, 2.0 PrimalSpaceLayer) with no cell to draw: a graph of their own only."""
    states: dict[str, int] = defaultdict(int)
    for st in doc.states:
        states[st.layer] += 1
    return [
        LayerNote(layer.id, 0, f"no cell with a footprint (a graph of {states[layer.id]} states)", layer.name)
        for layer in doc.layers
        if layer.kind_name in ("spacelayer", "primalspacelayer") and layer.id not in by_layer
    ]


def _asked(doc: RawDocument, by_layer: dict[str, list[KeptCell]], wanted: Sequence[str]) -> set[str]:
    """The layers ``--layer`` names (by id or name; a 2.0 ThematicLayer names the layers inside it)."""
    kept: set[str] = set()
    known = [f"{lid} ({info.name})" if (info := _info(doc, lid)) and info.name else lid for lid in by_layer if lid]
    for word in wanted:
        hits = {
            layer.id
            for layer in doc.layers
            if word in (layer.id, layer.name) or (layer.parent and word in (layer.parent, _name(doc, layer.parent)))
        } & set(by_layer)
        if not hits:
            raise UnknownLayer(
                f"{doc.path}: no layer with cells to draw is named {word!r}; layers with cells: "
                f"{', '.join(known) or 'none'}",
                path=str(doc.path),
                layer=word,
                known=known,
                hint="Give --layer one of the layers listed.",
            )
        kept |= hits
    return kept


def _info(doc: RawDocument, lid: str) -> RawLayer | None:
    return next((layer for layer in doc.layers if layer.id == lid), None)


def _name(doc: RawDocument, lid: str) -> str:
    info = _info(doc, lid)
    return info.name if info else ""


def _same_level(a: Footprint, b: Footprint) -> bool:
    """Two cells at the same height (a 2D plan, or z unknown: yes): storeys drawn as layers of their own
    cover the same ground and must not be taken for repeats of each other."""
    if a.z_min is None or a.z_max is None or b.z_min is None or b.z_max is None:
        return True
    ha, hb = a.z_max - a.z_min, b.z_max - b.z_min
    shared = min(a.z_max, b.z_max) - max(a.z_min, b.z_min)
    return shared > 0.25 * min(ha, hb) if min(ha, hb) > 0 else shared >= -1e-9 * (1 + abs(a.z_min))


def _inside(cells: list[KeptCell], base: list[KeptCell]) -> tuple[float, int]:
    """Share of ``cells``' area inside ``base`` cells at the same height, and how many of ``cells`` lie
    partly inside and partly outside (5-95 %): a zone across rooms, as a room or a wing never does."""
    if not cells or not base:
        return 0.0, 0
    tree = shapely.STRtree([b.geometry for b in base])
    total = inside = 0.0
    straddling = 0
    for c in cells:
        area = c.geometry.area
        near = [base[i].geometry for i in tree.query(c.geometry) if _same_level(c.fp, base[i].fp)]
        part = c.geometry.intersection(_filled(near)).area if near and area > 0 else 0.0
        total, inside = total + area, inside + part
        straddling += 0.05 < part / area < 0.95 if area > 0 else 0
    return (inside / total if total > 0 else 0.0), straddling


def _filled(geoms: list[BaseGeometry]) -> BaseGeometry:
    """The union of ``geoms`` with their holes filled: a layer whose cells fill the voids of the base
    layer's cells (InEditor's "sub" layer in a corridor's stair core) describes the same building."""
    parts = shapely.get_parts(np.asarray(geoms, dtype=object))
    return shapely.union_all(shapely.polygons(shapely.get_exterior_ring(parts)))


def _note(
    lid: str, cells: list[KeptCell], reason: str, doc: RawDocument, notes: list[LayerNote], warnings: list[str]
) -> None:
    notes.append(LayerNote(lid, len(cells), reason, _name(doc, lid)))
    warnings.append(f"layer {lid!r} ({len(cells)} cells) not drawn: {reason}")


def select_layers(
    cells: list[KeptCell], doc: RawDocument, alma: str, warnings: list[str], wanted: Sequence[str] = ()
) -> tuple[list[KeptCell], list[LayerNote]]:
    """The cells of the layer(s) to draw, and a note for each layer not drawn.

    The navigable layer is the one whose cells the navigation graph connects; the layers' own words
    (1.x class/usage/function, 2.0 ThematicLayer theme) come next; a layer that lies mostly inside the
    drawn one repeats or subdivides it. Thematic layers (light zones, sensor coverage) overlap rooms and
    reach outside the building: drawn, their outlines would become walls across rooms. ``wanted``
    (``--layer``) draws the named layers instead."""
    by_layer: dict[str, list[KeptCell]] = defaultdict(list)
    for c in cells:
        by_layer[c.layer].append(c)
    notes = _no_cells(doc, by_layer)
    order = [layer.id for layer in doc.layers if layer.id in by_layer]
    if wanted:
        kept = _asked(doc, by_layer, wanted)
        for lid in order:
            if lid not in kept:
                _note(lid, by_layer[lid], f"not asked for (--layer {', '.join(wanted)})", doc, notes, warnings)
        return _with_obstacles([c for c in cells if c.layer in kept], by_layer, notes, warnings)
    if len(order) <= 1:
        return cells, notes
    info = {layer.id: layer for layer in doc.layers}
    if alma:
        geo = [
            lid
            for lid in order
            if lid == "L1" or (info[lid].cls.upper() == "TOPOGRAPHIC" and info[lid].usage.lower() == "geometry")
        ]
        keep = geo[:1] or order[:1]
        for lid in order:
            if lid not in keep:
                _note(lid, by_layer[lid], f"ALMA style: geometry from layer {keep[0]!r} only", doc, notes, warnings)
        return [c for c in cells if c.layer in keep or c.layer == ""], notes
    linked = {c for pair in linked_pairs(doc) for c in pair}
    joined = {lid: sum(c.raw.id in linked for c in by_layer[lid]) for lid in order}
    words = {lid: _words(info[lid], info) for lid in order}
    primary = min(order, key=lambda lid: (bool(words[lid][1]), not joined[lid], not words[lid][0], order.index(lid)))
    kept = {primary, ""}
    base = by_layer[primary] + by_layer.get("", [])
    for lid in order:
        if lid == primary:
            continue
        if all(c.raw.kind_name in OBSTACLE_NAMES for c in by_layer[lid]) and not words[lid][1]:
            kept.add(lid)  # columns, installations: obstacles (occupied), never floor; no graph joins them
            continue
        if words[lid][1] and not words[primary][1]:
            reason = f"a thematic layer ({words[lid][1]}), not the navigable space of layer {primary!r}"
        elif joined[primary] and not joined[lid]:
            reason = (
                f"the navigation graph connects none of its cells (it connects {joined[primary]} cells "
                f"of layer {primary!r}, which is drawn)"
            )
        else:
            share, straddling = _inside(by_layer[lid], base)
            if share > 0.5:
                reason = f"{share:.0%} of it lies inside layer {primary!r}: it repeats or subdivides it"
            elif 2 * straddling > len(by_layer[lid]):
                reason = (
                    f"{straddling} of its {len(by_layer[lid])} cells lie partly inside the rooms of layer "
                    f"{primary!r} and partly outside them: zones over the building, not rooms"
                )
            else:
                kept.add(lid)
                base = base + by_layer[lid]
                continue
        _note(lid, by_layer[lid], reason, doc, notes, warnings)
    return _with_obstacles([c for c in cells if c.layer in kept], by_layer, notes, warnings)


def _with_obstacles(
    drawn: list[KeptCell], by_layer: dict[str, list[KeptCell]], notes: list[LayerNote], warnings: list[str]
) -> tuple[list[KeptCell], list[LayerNote]]:
    """``drawn`` plus the non-navigable cells (NonNavigableSpace: columns, fixed furniture, voids) of the
    layers not drawn that lie inside the drawn floor at its height: non-navigable space is an obstacle
    whichever layer holds it, and left out it came out free inside rooms (issue 37). Each such layer's
    note counts them."""
    out, tree = list(drawn), shapely.STRtree([c.geometry for c in drawn]) if drawn else None
    for i, note in enumerate(notes):
        blocked = [c for c in by_layer.get(note.id, []) if c.raw.kind_name in OBSTACLE_NAMES]
        inside = [c for c in blocked if tree is not None and _on_floor(c, drawn, tree)]
        if inside:
            out += inside
            notes[i] = replace(note, obstacles=len(inside))
            warnings.append(f"layer {note.id!r}: {len(inside)} non-navigable cells inside the floor drawn as obstacles")
    return out, notes


def _on_floor(cell: KeptCell, drawn: list[KeptCell], tree: shapely.STRtree) -> bool:
    """Whether ``cell`` overlaps a drawn cell at the same height (by area, not a touch at an edge)."""
    return any(
        _same_level(cell.fp, drawn[j].fp)
        and cell.geometry.intersection(drawn[j].geometry).area > 1e-9 * (1 + cell.geometry.area)
        for j in tree.query(cell.geometry).tolist()
    )


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
            + (
                f"; the file holds only a navigation graph ({len(doc.states)} states, "
                f"{len(doc.transitions)} transitions)"
                if graph_only
                else ""
            ),
            path=str(doc.path),
            element="CellSpace",
            hint="A map is drawn from the cells' shapes: export the building with its CellSpace geometry "
            "(Geometry2D or Geometry3D) as well as the graph.",
        )
    return cells
