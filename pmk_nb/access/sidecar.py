"""The rooms sidecar: a storey's rooms, doors, navigation links and openings, next to its map YAML.

``NAME.rooms.json`` travels with the map (same stem, map frame, metres) so that the accessibility
check can run on a written map alone (``pmk check MAP.yaml``), and so that the dashboard can name
rooms and plan routes without the building file. Geometry is GeoJSON (``shapely.to_geojson``).
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import shapely

from pmk_nb.errors import MapFormatError, MapNotFound
from pmk_nb.indoorgml import Cell, CellKind, Link
from pmk_nb.openings import Opening, Skipped

if TYPE_CHECKING:
    from pmk_nb.indoorgml import Building
    from pmk_nb.openings import OpeningPlan

FORMAT = "pmk-rooms/1"
SUFFIX = ".rooms.json"


def sidecar_path(yaml_path: str | Path) -> Path:
    """Where the sidecar of the map ``yaml_path`` lives."""
    p = Path(yaml_path)
    return p.with_name(p.stem + SUFFIX)


def sidecar_doc(yaml_path: str | Path) -> dict[str, Any] | None:
    """The rooms file of a map as written, or None when it is missing or unreadable (screens and
    listings show what is there; :func:`read_sidecar` is the strict reader that says what is wrong)."""
    try:
        doc = json.loads(sidecar_path(yaml_path).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return doc if isinstance(doc, dict) else None


def _geo(g: Any) -> Any:
    return None if g is None or g.is_empty else json.loads(shapely.to_geojson(g))


def _shape(obj: Any) -> Any:
    return None if obj is None else shapely.from_geojson(json.dumps(obj))


def sidecar_json(building: Building, storey: str, plan: OpeningPlan, report: dict[str, Any] | None) -> dict[str, Any]:
    """The sidecar document of one storey."""
    cells = [c for c in building.cells_of(storey) if c.footprint is not None and not c.footprint.is_empty]
    names = {c.id for c in cells}
    return {
        "format": FORMAT,
        "storey": storey,
        "frame": "map",
        "source": Path(building.source).name,
        "unit": building.unit,
        "unit_conflict": building.unit_conflict,
        "graph": building.graph_status.to_json(),  # the Maps screen says when it was lost
        "skipped_layers": [asdict(n) for n in building.skipped_layers],
        "unit_suspect": asdict(building.unit_suspect) if building.unit_suspect is not None else None,
        "rooms": [
            {"id": c.id, "name": c.name, "kind": c.kind.value, "z_min": c.z_min, "polygon": _geo(c.footprint)}
            for c in cells
        ],
        "doors": [
            {"id": d.id, "name": d.name, "geometry": _geo(d.geometry), "width": round(d.geometry.length, 3)}
            for d in building.doors_of(storey)
            if d.geometry is not None and not d.geometry.is_empty
        ],
        "links": [
            {"id": k.id, "a": k.a, "b": k.b, "storeys": list(k.storeys), "line": _geo(k.line)}
            for k in building.links
            if k.a in names or k.b in names
        ],
        "openings": [
            {
                "link": o.link.id,
                "rule": o.rule,
                "width": round(o.width, 3),
                "gap": round(o.gap, 3),
                "segments": [_geo(s) for s in o.segments],
                "reaches": [round(r, 3) for r in o.reaches],
                **({"path": _geo(o.path)} if o.path is not None else {}),
            }
            for o in plan.openings
        ],
        "skipped": [{"link": k.link.id, "reason": k.reason} for k in plan.skipped],
        "accessibility": report,
    }


@dataclass(frozen=True)
class StoreyPlanFile:
    """A sidecar read back: the cells and openings the accessibility check needs."""

    storey: str
    cells: list[Cell]
    openings: list[Opening]
    raw: dict[str, Any]
    skipped: tuple[Skipped, ...] = ()  # links left without an opening (none in files written before them)


class NoRoomsFile(MapFormatError):
    """A map with no rooms file beside it: nothing to check it against.

    Attributes:
        path: the rooms file that is not there.
        map_path: the map's YAML.
        converted: True when the YAML says PMK Notebook wrote it (then converting the plan again writes the
            rooms file); False for a map made elsewhere, e.g. by SLAM, which no plan's graph describes.
    """

    def __init__(self, path: Path, map_path: Path, *, converted: bool) -> None:
        if converted:
            hint = "Convert the building plan again: maps made before this version have no rooms file."
        else:
            hint = (
                "This map was not converted from a building plan (a SLAM or hand-drawn map has no navigation "
                "graph to check): check the building plan instead, `pmk check PLAN.gml`."
            )
        super().__init__(f"{path.name}: not found beside {map_path.name}", path=str(path), hint=hint)
        self.map_path = str(map_path)
        self.converted = converted


def _converted_here(yaml_path: Path) -> bool:
    """The map's YAML names PMK Notebook as its writer (rosmap.write_map's ``generator``)."""
    from pmk_nb.rosmap import read_map_yaml

    try:
        return str(read_map_yaml(yaml_path).extras.get("generator", "")).startswith("pmk_nb")
    except MapFormatError:
        return False


def map_missing(yaml_path: str | Path) -> None:
    """Raise :class:`MapNotFound` (naming the maps that are there) when the map itself is not there:
    a missing map is not a missing rooms file."""
    p = Path(yaml_path)
    if p.is_file():
        return
    folder = p.parent
    present = sorted(y.stem for y in folder.glob("*.yaml")) if folder.is_dir() else []
    raise MapNotFound(str(p), name=p.stem, folder=str(folder), present=present)


def read_sidecar(yaml_path: str | Path) -> StoreyPlanFile:
    """Read the sidecar of map ``yaml_path``.

    Raises:
        MapNotFound: no map at ``yaml_path`` (a missing map is not a missing rooms file).
        NoRoomsFile: no sidecar (says whether converting the plan again would write one).
        MapFormatError: a sidecar this version cannot read (names the file).
    """
    path = sidecar_path(yaml_path)
    map_missing(yaml_path)
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError as err:
        raise NoRoomsFile(path, Path(yaml_path), converted=_converted_here(Path(yaml_path))) from err
    except (OSError, ValueError) as err:
        raise MapFormatError(f"{path}: not a readable rooms file ({err})", path=str(path)) from err
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise MapFormatError(f"{path}: not a {FORMAT} rooms file", path=str(path))
    try:
        storey = str(doc["storey"])
        cells = [
            Cell(r["id"], CellKind(r["kind"]), _shape(r["polygon"]), storey, r.get("name", ""), z_min=r.get("z_min"))
            for r in doc["rooms"]
            if r.get("polygon")
        ]
        links = {
            k["id"]: Link(k["id"], k["a"], k["b"], _shape(k.get("line")), tuple(k["storeys"])) for k in doc["links"]
        }
        label = {c.id: c.name or c.id for c in cells}
        openings = [
            Opening(
                links[o["link"]],
                o["rule"],
                tuple(_shape(s) for s in o["segments"]),
                float(o["width"]),
                float(o["gap"]),
                (label[links[o["link"]].a], label[links[o["link"]].b]),
                tuple(float(r) for r in o.get("reaches", [])),
                _shape(o["path"]) if o.get("path") else None,
            )
            for o in doc["openings"]
        ]
        skipped = tuple(
            Skipped(links[k["link"]], (label[links[k["link"]].a], label[links[k["link"]].b]), str(k["reason"]))
            for k in doc.get("skipped", [])
        )
    except (KeyError, TypeError, ValueError, shapely.errors.GEOSException) as err:
        raise MapFormatError(f"{path}: damaged rooms file ({err!r})", path=str(path)) from err
    return StoreyPlanFile(storey, cells, openings, doc, skipped)
