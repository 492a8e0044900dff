"""A JSON-able digest of a Building (for `pmk info`, the maps list and logs)."""

from __future__ import annotations

from dataclasses import asdict
from typing import Any

import shapely

from pmk_nb.indoorgml.model import Building
from pmk_nb.indoorgml.units import UnitVote, vote_words


def _r(v: float | None) -> float | None:
    return None if v is None else round(float(v), 3)


def summarize(building: Building) -> dict[str, Any]:
    """Return version, namespaces, units, storeys (cells, extents in metres), doors, graph, georef."""
    storeys = []
    for st in building.storeys:
        cells = [building.cells[i] for i in st.cell_ids]
        kinds: dict[str, int] = {}
        for c in cells:
            kinds[c.kind.value] = kinds.get(c.kind.value, 0) + 1
        extent = None
        if cells:
            minx, miny, maxx, maxy = shapely.union_all([c.footprint for c in cells]).bounds
            extent = {
                "min": [_r(minx), _r(miny)],
                "max": [_r(maxx), _r(maxy)],
                "size": [_r(maxx - minx), _r(maxy - miny)],
            }
        door_cells = sum(1 for c in cells if c.kind.is_door)
        storeys.append(
            {
                "name": st.name,
                "elevation": _r(st.elevation),
                "source": st.source,
                "cells": len(cells),
                "kinds": kinds,
                "doors": len(building.doors_of(st.name)) + door_cells,
                "extent": extent,
            }
        )
    door_boundaries = sum(1 for b in building.boundaries.values() if b.is_door)
    door_cells = sum(1 for c in building.cells.values() if c.kind.is_door)
    g = building.georef
    return {
        "source": building.source,
        "sha256": building.sha256,
        "version": building.version,
        "namespaces": dict(building.namespaces),
        "unit": building.unit,
        "unit_reason": building.unit_reason,
        "unit_votes": [asdict(v) for v in building.unit_votes],
        "storeys": storeys,
        "cells": len(building.cells),
        "boundaries": len(building.boundaries),
        "doors": {"boundaries": door_boundaries, "cells": door_cells, "total": door_boundaries + door_cells},
        "graph": {"states": len(building.graph.states), "transitions": len(building.graph.transitions)},
        "graph_status": building.graph_status.to_json(),
        "layers": list(building.layers),
        "skipped_layers": [asdict(note) for note in building.skipped_layers],
        "geometry_layers": sorted({c.layer for c in building.cells.values()}),
        "georeference": {
            "translation": [_r(g.translation[0]), _r(g.translation[1])],
            "rotation": g.rotation,
            "lla": list(g.lla) if g.lla else None,
            "srs_name": g.srs_name,
            "origin": [_r(g.origin[0]), _r(g.origin[1])],
        },
        "overlaps": [asdict(o) for o in building.overlaps],
        "warnings": list(building.warnings),
    }


SHOWN_OVERLAPS = 10  # pairs listed by name; the rest counted


def overlap_lines(overlaps: list[dict[str, Any]]) -> list[str]:
    """The cells of one storey that overlap (IndoorGML cells must not), largest overlap first."""
    if not overlaps:
        return []
    n = len(overlaps)
    lines = [f"  OVERLAPPING CELLS ({n} pair{'s' if n != 1 else ''}; the map draws each pair as one space):"]
    for o in overlaps[:SHOWN_OVERLAPS]:
        lines.append(
            f"    - {o['a']} and {o['b']} (storey {o['storey']}): {o['area']:.3g} m², "
            f"{o['share']:.1%} of the smaller cell"
        )
    if len(overlaps) > SHOWN_OVERLAPS:
        lines.append(f"    ... and {len(overlaps) - SHOWN_OVERLAPS} more (pmk info --json lists them all)")
    return lines


def vote_lines(votes: list[dict[str, Any]]) -> list[str]:
    """The unit evidence, vote by vote (what each kind measured, the unit it says)."""
    if not votes:
        return []
    lines = [f"  unit votes: {vote_words(UnitVote(**{**v, 'units': tuple(v['units'])}) for v in votes)}"]
    lines += [f"    - {v['source']}: {', '.join(v['units']) or 'no unit'} ({v['detail']})" for v in votes]
    return lines


def layer_lines(skipped: list[dict[str, Any]]) -> list[str]:
    """The layers not drawn and why (``pmk info``, ``pmk convert``); ``--layer`` draws one on request."""
    if not skipped:
        return []
    hint = "; pmk convert --layer NAME draws one" if any(note["cells"] for note in skipped) else ""
    lines = [f"  layers not drawn ({len(skipped)}{hint}):"]
    for note in skipped:
        label = f"{note['id']} ({note['name']})" if note["name"] and note["name"] != note["id"] else note["id"]
        lines.append(f"    - {label}, {note['cells']} cells: {note['reason']}")
        if note.get("obstacles"):
            lines.append(f"      drawn as obstacles: {note['obstacles']} cells from layer {note['id']}")
    return lines


def graph_lines(status: dict[str, Any]) -> list[str]:
    """The graph's state in one loud line when it is lost or absent, or partly dangling."""
    if status["lost"]:
        return [f"  NAVIGATION GRAPH NOT USED: {status['reason']}"]
    if status["dangling"]:
        return [
            f"  graph warning: {status['dangling']} of {status['transitions']} transitions name states "
            f"that are not in the file; {status['resolved']} join drawn cells"
        ]
    return []


def format_summary(summary: dict[str, Any]) -> str:
    """Human-readable text for :func:`summarize`'s dict."""
    lines = [
        f"{summary['source']}",
        f"  IndoorGML version: {summary['version']}",
        f"  units: {summary['unit']} ({summary['unit_reason']})",
        *vote_lines(summary["unit_votes"]),
        f"  cells: {summary['cells']}   doors: {summary['doors']['total']} "
        f"({summary['doors']['boundaries']} boundaries, {summary['doors']['cells']} door cells)",
        f"  graph: {summary['graph']['states']} states, {summary['graph']['transitions']} transitions",
        f"  layers: {', '.join(summary['layers']) or '-'} (geometry from: "
        f"{', '.join(x or '(primal features)' for x in summary['geometry_layers'])})",
        *layer_lines(summary["skipped_layers"]),
        *graph_lines(summary["graph_status"]),
        *overlap_lines(summary["overlaps"]),
        f"  storeys: {len(summary['storeys'])}",
    ]
    for st in summary["storeys"]:
        ext = st["extent"]
        size = f"{ext['size'][0]:.2f} x {ext['size'][1]:.2f} m at ({ext['min'][0]}, {ext['min'][1]})" if ext else "-"
        elev = "?" if st["elevation"] is None else f"{st['elevation']:.2f} m"
        lines.append(
            f"    {st['name']:>6}: {st['cells']:3d} cells, {st['doors']:3d} doors, floor {elev}, "
            f"{size} [{st['source']}]"
        )
    g = summary["georeference"]
    lines.append(
        f"  georeference: translation {g['translation']} m, rotation {g['rotation']} deg"
        + (f", lla {g['lla']}" if g["lla"] else "")
        + (f", srs {g['srs_name']}" if g["srs_name"] else "")
        + (f", map origin at {g['origin']} m in the CRS" if any(g["origin"]) else "")
    )
    ns = ", ".join(f"{k or '(default)'}={v}" for k, v in summary["namespaces"].items())
    lines.append(f"  namespaces: {ns}")
    if summary["warnings"]:
        lines.append(f"  warnings ({len(summary['warnings'])}):")
        lines.extend(f"    - {w}" for w in summary["warnings"])
    return "\n".join(lines)
