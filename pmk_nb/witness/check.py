"""The witness's entry points: a written map against the plan it names, or a grid in memory."""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import TYPE_CHECKING

from pmk_nb.errors import PmkError
from pmk_nb.witness.storey import witness_storey

if TYPE_CHECKING:
    from pmk_nb.grid import OccupancyGrid
    from pmk_nb.indoorgml import Building
    from pmk_nb.witness.findings import WitnessReport


class PlanNotFound(PmkError):
    """The map names a plan that is not where it says (nor beside the map).

    Attributes:
        map_path: the map YAML; source: the plan as the YAML names it ('' when it names none).
    """

    def __init__(self, *, map_path: str, source: str) -> None:
        said = f"names its plan {source!r}, which is not there" if source else "names no plan (no 'source' key)"
        super().__init__(
            f"{map_path}: the map {said}: the witness needs the plan to judge the map",
            hint="Give the plan with --plan FILE.",
        )
        self.map_path = map_path
        self.source = source


class PlanChanged(PmkError):
    """The plan found is not the one the map was converted from (its SHA-256 differs).

    Attributes:
        plan: the file found; expected, actual: the SHA-256 the map records and the file's.
    """

    def __init__(self, *, plan: str, expected: str, actual: str) -> None:
        super().__init__(
            f"{plan} is not the plan this map was converted from "
            f"(SHA-256 {actual[:12]}…, the map says {expected[:12]}…)",
            hint="Convert the plan again, or give the original with --plan FILE.",
        )
        self.plan, self.expected, self.actual = plan, expected, actual


def witness_grid(building: Building, grid: OccupancyGrid, *, chair_width: float) -> WitnessReport:
    """One storey's grid (its ``meta['storey']`` names it) against the building."""
    storey = str(grid.meta.get("storey", building.storeys[0].name if building.storeys else ""))
    thick = grid.meta.get("wall_thickness")
    return witness_storey(
        building, storey, grid, chair_width=chair_width, wall_thickness=None if thick is None else float(thick)
    )


def find_plan(yaml_path: Path, source: str, source_path: str = "") -> Path:
    """The plan a map names: where it was converted from (``source_path``), as written, from the map's
    folder, or by its file name beside the map."""
    if source or source_path:
        named = Path(source or source_path)
        candidates = [Path(source_path)] if source_path else []
        candidates += [named, yaml_path.parent / named, yaml_path.parent / named.name]
        for candidate in candidates:
            if candidate.is_file():
                return candidate
    raise PlanNotFound(map_path=str(yaml_path), source=source or source_path)


def witness_map(
    yaml_path: str | Path,
    *,
    chair_width: float,
    plan: str | Path | None = None,
    layers: tuple[str, ...] = (),
    not_windows: tuple[str, ...] = (),
) -> tuple[WitnessReport, OccupancyGrid]:
    """A written map (YAML + image, read as map_server reads it) against its plan, read afresh.

    Raises:
        PlanNotFound, PlanChanged; MapFormatError and IndoorGMLError for files that cannot be read.
    """
    from pmk_nb.indoorgml import read_building
    from pmk_nb.rosmap import read_map

    path = Path(yaml_path)
    grid = read_map(path)
    source = str(grid.meta.get("source") or "")
    source_path = str(grid.meta.get("source_path") or "")
    plan_path = Path(plan) if plan is not None else find_plan(path, source, source_path)
    expected = str(grid.meta.get("source_sha256") or "")
    if plan is None and expected:
        actual = hashlib.sha256(plan_path.read_bytes()).hexdigest()
        if actual != expected:
            raise PlanChanged(plan=str(plan_path), expected=expected, actual=actual)
    unit = str(grid.meta.get("unit") or "auto")
    building = read_building(plan_path, unit=unit, layers=layers, not_windows=not_windows)
    return witness_grid(building, grid, chair_width=chair_width), grid
