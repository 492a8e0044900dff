"""Raw records -> :class:`Building`: layers, kinds, units, storeys, doors, graph, georeference."""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence
from typing import overload

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pmk_nb.errors import IndoorGMLError
from pmk_nb.indoorgml import doors as doorlib
from pmk_nb.indoorgml.crs import CRS_AUTO, MAX_EXTENT_M, Frame, choose_frame, refuse_extent, shift
from pmk_nb.indoorgml.drafts import DRAFT_VERSION, is_draft
from pmk_nb.indoorgml.footprint import Footprint, boundary_footprints, floor_height
from pmk_nb.indoorgml.graph import graph_status, linked_pairs, nav_graph, resolve_links, state_cells
from pmk_nb.indoorgml.layers import KeptCell, select_layers, usable_cells
from pmk_nb.indoorgml.levels import RAISED, WINDOW_DEPTH, not_window_ids, raised_cells
from pmk_nb.indoorgml.model import Boundary, Building, Cell, CellKind, Georeference, Storey
from pmk_nb.indoorgml.overlaps import find_overlaps
from pmk_nb.indoorgml.records import RawCell, RawDocument
from pmk_nb.indoorgml.storeys import CellZ, StoreyPlan, plan_storeys, split_levels
from pmk_nb.indoorgml.unit_evidence import gather
from pmk_nb.indoorgml.units import UNIT_SCALE, UnitChoice, UnitEvidence, choose_unit, unit_suspect

KIND_BY_NAME = {
    "navigablespace": CellKind.NAVIGABLE,
    "generalspace": CellKind.GENERAL,
    "transitionspace": CellKind.TRANSITION,
    "transferspace": CellKind.TRANSITION,
    "connectionspace": CellKind.CONNECTION,
    "anchorspace": CellKind.ANCHOR,
    "nonnavigablespace": CellKind.NON_NAVIGABLE,
    "obstacle": CellKind.NON_NAVIGABLE,
}


def detect_alma(doc: RawDocument) -> str:
    """Why this file is ALMA style ('' if it is not); structural, so any prefix works."""
    uris = {v.lower() for v in doc.namespaces.values()}
    if any("idsia.ch/alma" in u for u in uris):
        return "alma namespace"
    inline = any(c.alma_inline for c in doc.cells) and not is_draft(doc)  # the 0.8/0.9 drafts nest cells too
    if doc.root == "multilayeredgraph" and inline:
        return "MultiLayeredGraph root with cells inline in State/duality"
    if doc.translation is not None and inline:
        return "cells inline in State/duality and a map-frame translation"
    if {"indoorCore", "indoorNavi"} & set(doc.namespaces) and inline:
        return "indoorCore/indoorNavi prefixes with cells inline in State/duality"
    return ""


def _version(doc: RawDocument, alma: str) -> str:
    if alma or is_draft(doc):
        return "alma" if alma else DRAFT_VERSION
    uris = " ".join(doc.namespaces.values()).lower()
    if "indoorgml/2.0" in uris or doc.has_primal_layer:
        return "2.0"
    if doc.has_level or "indoorgml/1.1" in uris:
        return "1.1"
    if any(c.wrapped for c in doc.cells):
        return "1.0.3"
    return "1.0"


def _kind(raw: RawCell, alma: bool) -> CellKind:
    kind = KIND_BY_NAME.get(raw.kind_name)
    if kind is not None:
        return kind  # a name saying "door" is weighed later, with the cell's size (_named_doors)
    # ALMA convention (original app and idsia reader): only navi spaces are navigable
    return CellKind.NON_NAVIGABLE if alma else CellKind.NAVIGABLE


@overload
def _scale(geom: BaseGeometry, s: float) -> BaseGeometry: ...
@overload
def _scale(geom: None, s: float) -> None: ...
@overload
def _scale(geom: BaseGeometry | None, s: float) -> BaseGeometry | None: ...
def _scale(geom: BaseGeometry | None, s: float) -> BaseGeometry | None:
    if geom is None or s == 1.0:
        return geom
    return shapely.transform(geom, lambda xy: xy * s)


def _zs(v: float | None, s: float) -> float | None:
    return None if v is None else v * s


def build_building(
    doc: RawDocument,
    sha256: str,
    unit: str,
    not_windows: Sequence[str] = (),
    layers: Sequence[str] = (),
    crs: str = CRS_AUTO,
) -> Building:
    """Interpret ``doc``: frame -> cells -> kinds -> boundaries and doors -> unit -> storeys -> the model.
    ``not_windows``: ids or names of cells the window rule must leave free (see levels.not_window_ids);
    ``layers``: ids or names of the layers to draw instead of the navigable one (see layers.select_layers);
    ``crs``: the frame of the coordinates (see :mod:`pmk_nb.indoorgml.crs`). ``doc`` is moved to the frame."""
    warnings: list[str] = []
    frame = choose_frame(doc, crs)
    shift(doc, frame.origin)
    doc.srs_name = frame.srs
    alma = detect_alma(doc)
    cells, skipped = select_layers(usable_cells(doc, warnings), doc, alma, warnings, layers)
    keep = not_window_ids(((c.raw.id, c.raw.name) for c in cells), not_windows, str(doc.path))
    kinds = {c.raw.id: _kind(c.raw, bool(alma)) for c in cells}
    bfps = _classify_boundaries(doc, cells, warnings)
    choice = _unit_and_names(doc, cells, unit, alma, kinds, bfps, warnings)
    unit, reason = choice.unit, choice.reason
    s = UNIT_SCALE[unit]
    plan = plan_storeys(
        [CellZ(c.raw.id, _zs(c.fp.z_min, s), _zs(c.fp.z_max, s), c.raw.storey_hint, c.raw.storey_source) for c in cells]
    )
    cell_notes: list[str] = []
    linked = linked_pairs(doc)
    model_cells = _model_cells(cells, kinds, plan, s, cell_notes, linked, keep)
    graph = nav_graph(doc, model_cells, s)
    links = resolve_links(graph, model_cells)
    stairs = frozenset(c.raw.id for c in cells if c.fp.stepped)
    levels = split_levels(
        plan, {i: (c.z_min, c.name) for i, c in model_cells.items()}, [(k.a, k.b) for k in links], stairs
    )
    if levels is not plan:  # split levels: cells, windows and links are decided again on the new storeys
        plan, cell_notes = levels, []
        model_cells = _model_cells(cells, kinds, plan, s, cell_notes, linked, keep)
        graph = nav_graph(doc, model_cells, s)
        links = resolve_links(graph, model_cells)
    status = graph_status(doc, graph, model_cells, warnings)
    warnings.extend(plan.notes + cell_notes)
    storeys = [
        Storey(n, plan.elevation[n], [i for i, c in model_cells.items() if c.storey == n], plan.source[n])
        for n in plan.names
    ]
    _stats_warnings(doc, warnings)
    return Building(
        source=str(doc.path),
        sha256=sha256,
        version=_version(doc, alma),
        namespaces=doc.namespaces,
        unit=unit,
        unit_reason=reason,
        storeys=storeys,
        cells=model_cells,
        boundaries=_boundaries(doc, bfps, _boundary_refs(cells), model_cells, storeys, s),
        graph=graph,
        georef=_georef(doc, s, frame),
        layers=[layer.id for layer in doc.layers],
        warnings=warnings,
        links=links,
        unit_conflict=choice.conflict,
        unit_suspect=choice.suspect,
        unit_votes=list(choice.votes),
        skipped_layers=skipped,
        graph_status=status,
        overlaps=find_overlaps((st.name, [model_cells[i] for i in st.cell_ids]) for st in storeys),
    )


def _unit_and_names(
    doc: RawDocument,
    cells: list[KeptCell],
    unit: str,
    alma: str,
    kinds: dict[str, CellKind],
    bfps: dict[str, tuple[Footprint, str]],
    warnings: list[str],
) -> UnitChoice:
    """The unit judged without the doors only names make, then with those doors.named_doors finds door-sized."""
    unnamed = {b: (fp, "" if ev == "name" else ev) for b, (fp, ev) in bfps.items()}
    choice = _choose_unit(doc, cells, unit, alma, gather(doc, cells, kinds, unnamed))
    plain = [(c.raw.id, c.raw.name, c.geometry) for c in cells if c.raw.kind_name not in KIND_BY_NAME]
    named = [(b, fp.geometry) for b, (fp, ev) in bfps.items() if ev == "name"]
    doors, walls = doorlib.named_doors(plain, named, UNIT_SCALE[choice.unit], warnings)
    kinds.update(dict.fromkeys(doors, CellKind.CONNECTION))
    bfps.update((b, (bfps[b][0], "")) for b in walls)
    if doors or len(walls) < len(named):  # door widths the first judgement left out
        choice = _choose_unit(doc, cells, unit, alma, gather(doc, cells, kinds, bfps))
    return choice


def _boundary_refs(cells: list[KeptCell]) -> dict[str, list[str]]:
    """Boundary id -> ids of the kept cells that name it."""
    refs: dict[str, list[str]] = defaultdict(list)
    for c in cells:
        for r in c.raw.boundary_refs:
            refs[r].append(c.raw.id)
    return refs


def _owners(doc: RawDocument) -> dict[str, set[str]]:
    """Boundary id -> every cell (of any layer) that names it or whose transition it is dual to."""
    owners: dict[str, set[str]] = defaultdict(set)
    for raw in doc.cells:
        for r in raw.boundary_refs:
            owners[r].add(raw.id)
    state_cell = state_cells(doc)
    for t in doc.transitions:
        if t.duality:
            owners[t.duality].update(c for c in (state_cell.get(x) for x in t.connects) if c)
    return owners


def _classify_boundaries(
    doc: RawDocument, cells: list[KeptCell], warnings: list[str]
) -> dict[str, tuple[Footprint, str]]:
    """Footprint and door flag of each boundary that belongs to a kept cell (file units; scale-free rules)."""
    trans_dual = {t.duality for t in doc.transitions if t.duality}
    trans_ids = {t.id for t in doc.transitions}
    kept = {c.raw.id for c in cells}
    cell_geoms = [c.geometry for c in cells]
    cell_tree = shapely.STRtree(cell_geoms)  # boundary -> nearby cells without an O(B x C) scan
    owners = _owners(doc)
    bfps: dict[str, tuple[Footprint, str]] = {}
    seen: dict[tuple[object, ...], tuple[bool, set[str]]] = {}
    hint = {raw.id: raw.storey_hint for raw in doc.cells}
    dropped = dupes = walls = 0
    fps = boundary_footprints([(rb.polygons, rb.lines) for rb in doc.boundaries])
    for rb, fp in zip(doc.boundaries, fps, strict=True):
        if fp.geometry is not None:  # a copy is the same line at the same height on the same storey
            xy = tuple(sorted(map(tuple, np.round(shapely.get_coordinates(fp.geometry), 6).tolist())))
            storeys = frozenset(h for c in owners.get(rb.id, ()) if (h := hint.get(c)))
            key = (xy, _round(fp.z_min), _round(fp.z_max))
            unowned, taken = seen.get(key, (False, set()))  # copies kept so far: one unowned?, their storeys
            if key in seen and (unowned or not storeys or taken & storeys):
                dupes += 1  # an unowned copy ('-REVERSE') or one of the same storey
                continue
            seen[key] = (unowned or not storeys, taken | storeys)
        if owners.get(rb.id) and not owners[rb.id] & kept:
            dropped += 1
            continue
        dual = rb.id in trans_dual or (rb.duality in trans_ids if rb.duality else False)
        if rb.kind_name in doorlib.DOOR_TYPES:
            evidence = "type"
        elif (said := doorlib.named_evidence(dual, rb.kind_name, rb.id, rb.name, rb.description)) is not None:
            evidence = said  # a door by name; a window is wall unless a transition crosses it
        elif fp.geometry is not None and doorlib.partial_edge(
            fp.geometry, doorlib.near(cell_tree, cell_geoms, fp.geometry)
        ):
            evidence = "partial"
        elif dual:
            evidence = "duality"  # the face a transition crosses: may be a whole wall, not a door
        else:
            evidence = ""
        bfps[rb.id] = (fp, evidence)
    partial = [bid for bid, (_, ev) in bfps.items() if ev == "partial"]
    marked = [fp.geometry for fp, ev in bfps.values() if ev in ("type", "name") and fp.geometry is not None]
    marked_tree = shapely.STRtree(marked) if partial and marked else None
    for bid in partial if marked_tree is not None else ():  # the wall beside a marked door is wall, however short
        fp, geom = bfps[bid][0], bfps[bid][0].geometry
        assert marked_tree is not None and geom is not None  # partial: judged on its geometry, above
        if doorlib.continues_door(geom, doorlib.near(marked_tree, marked, geom, 1e-3)):
            bfps[bid], walls = (fp, ""), walls + 1
    if walls:
        warnings.append(f"{walls} short boundaries continue a door's wall: kept as wall, not taken for openings")
    if dropped:
        warnings.append(f"{dropped} boundaries belong only to cells of ignored layers - dropped")
    if dupes:
        warnings.append(f"{dupes} boundaries repeat another one's geometry (e.g. '-REVERSE' copies) - merged")
    return bfps


def _round(z: float | None) -> float | None:
    return None if z is None else round(z, 6)


def _choose_unit(doc: RawDocument, cells: list[KeptCell], unit: str, alma: str, evidence: UnitEvidence) -> UnitChoice:
    """The unit (given, or judged from the evidence) and why; refuses a plan larger than any building."""
    minx, miny, maxx, maxy = shapely.total_bounds([c.geometry for c in cells]).tolist()
    if unit == "auto":
        choice = choose_unit(alma=bool(alma), alma_why=alma, evidence=evidence)
    elif unit in UNIT_SCALE:
        choice = UnitChoice(unit, f"given: {unit}", suspect=unit_suspect(evidence, unit), votes=tuple(evidence.votes()))
    else:
        raise IndoorGMLError(
            f"{doc.path}: unknown unit {unit!r}; use one of auto, {', '.join(UNIT_SCALE)}", path=str(doc.path)
        )
    extent = max(maxx - minx, maxy - miny) * UNIT_SCALE[choice.unit]
    if extent > MAX_EXTENT_M:  # the cell farthest from the others' middle is the likely stray
        middles = shapely.get_coordinates(shapely.centroid([c.geometry for c in cells]))
        centre = np.tile(np.median(middles, axis=0), 2)  # (x, y, x, y): against a cell's bounds
        worst = max(cells, key=lambda c: float(np.abs(np.asarray(c.geometry.bounds) - centre).max()))
        refuse_extent(str(doc.path), doc.srs_name, extent, worst.raw.id, worst.raw.line)
    return choice


def _model_cells(
    cells: list[KeptCell],
    kinds: dict[str, CellKind],
    plan: StoreyPlan,
    s: float,
    warnings: list[str],
    linked: frozenset[frozenset[str]] = frozenset(),
    keep: frozenset[str] = frozenset(),
) -> dict[str, Cell]:
    """The model's cells in metres, on their storeys; raised free cells (windows, sills) become non-navigable,
    but those in ``keep`` (the user said they are not windows)."""
    model_cells: dict[str, Cell] = {}
    polygons = {c.raw.id: c.raw.polygons for c in cells}

    def floor_at(cell: str, x: float, y: float) -> float | None:
        return _zs(floor_height(polygons[cell], x, y, tol=0.05 / s), s)

    raised_ids = raised_cells(
        [(c.raw.id, c.geometry, _zs(c.fp.z_min, s), _zs(c.fp.z_max, s), plan.of_cell[c.raw.id]) for c in cells],
        touch=0.05 / s,
        linked=linked,
        thin=WINDOW_DEPTH / s,
        floor_at=floor_at,
    )
    raised: list[str] = []
    for c in cells:
        storey = plan.of_cell[c.raw.id]
        kind = kinds[c.raw.id]
        z_min, z_max = _zs(c.fp.z_min, s), _zs(c.fp.z_max, s)
        window = kind.is_free and c.raw.id in raised_ids and c.raw.id not in keep
        if window:
            kind = CellKind.NON_NAVIGABLE
            raised.append(c.raw.id)
        model_cells[c.raw.id] = Cell(
            id=c.raw.id,
            kind=kind,
            footprint=_scale(c.geometry, s),
            storey=storey,
            name=c.raw.name,
            layer=c.layer,
            z_min=z_min,
            z_max=z_max,
            boundary_ids=list(c.raw.boundary_refs),
            window=window,
        )
    if raised:
        warnings.append(
            f"{len(raised)} cells start more than {RAISED} m above a cell they touch (windows/sills): "
            f"treated as non-navigable: {raised[:8]}"
        )
    if spared := sorted(i for i in raised_ids if i in keep):
        warnings.append(f"{len(spared)} raised cells kept navigable as asked (--not-window): {spared[:8]}")
    return model_cells


def _georef(doc: RawDocument, s: float, frame: Frame) -> Georeference:
    return Georeference(
        translation=(doc.translation[0] * s, doc.translation[1] * s) if doc.translation else (0.0, 0.0),
        rotation=doc.rotation or 0.0,
        lla=doc.lla,
        srs_name=frame.srs,
        origin=(frame.origin[0] * s, frame.origin[1] * s),
    )


def _stats_warnings(doc: RawDocument, warnings: list[str]) -> None:
    st = doc.stats
    if st.unclosed:
        warnings.append(f"{st.unclosed} rings were not closed (closed them)")
    if st.repeated:
        warnings.append(f"{st.repeated} repeated consecutive points dropped")
    if st.interior_only:
        warnings.append(
            f"{st.interior_only} solids have interior shells but no exterior shell: "
            "their interior shells read as the solid (nothing to be a void in)"
        )


def _boundaries(
    doc: RawDocument,
    bfps: dict[str, tuple[Footprint, str]],
    refs: dict[str, list[str]],
    cells: dict[str, Cell],
    storeys: list[Storey],
    s: float,
) -> dict[str, Boundary]:
    out: dict[str, Boundary] = {}
    cell_list = list(cells.values())
    tree = shapely.STRtree([c.footprint for c in cell_list])
    for rb in doc.boundaries:
        if rb.id not in bfps:
            continue
        fp, evidence = bfps[rb.id]
        geom = _scale(fp.geometry, s)
        storey = next((cells[i].storey for i in refs.get(rb.id, []) if i in cells), None)
        if storey is None and geom is not None:
            touching = [cell_list[i] for i in tree.query(geom, predicate="dwithin", distance=0.05)]
            if (z_fp := fp.z_min) is not None:
                touching.sort(key=lambda c: abs((c.z_min or 0.0) - z_fp * s))
            storey = touching[0].storey if touching else None
        if storey is None and len(storeys) == 1:
            storey = storeys[0].name
        out[rb.id] = Boundary(rb.id, bool(evidence), geom, storey, rb.name, rb.virtual, evidence)
    return out
