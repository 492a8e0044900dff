"""The one convert pipeline: building plan -> one map_server set per storey, written all or nothing.

``pmk convert``, :meth:`pmk_nb.library.folder.MapsFolder.convert` and notebook 01 all call
:func:`convert_plan`, so the command line, the dashboard and the notebook make the same files.
Every storey is planned (size-checked) before any is rasterised; each storey's set is staged in a
hidden folder and the whole batch is moved into place with :func:`pmk_nb.fileio.replace_all`
(images first, YAMLs last), so a failure leaves the output folder as it was.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pmk_nb.access import StoreyReport, check_chair_width, check_grid, sidecar_json, sidecar_path
from pmk_nb.defaults import (
    DEFAULT_CHAIR_WIDTH,
    DEFAULT_DOOR_WIDTH,
    DEFAULT_MAX_CELLS,
    DEFAULT_MAX_WALL_GAP,
    DEFAULT_RESOLUTION,
    DEFAULT_WALL_THICKNESS,
)
from pmk_nb.errors import MapFormatError, OccupancyError
from pmk_nb.fileio import Content, replace_all
from pmk_nb.library.choices import CHOICES_KEY, ConvertChoices
from pmk_nb.library.naming import storey_map_names
from pmk_nb.openings import plan_openings
from pmk_nb.progress import ProgressCallback, emit, sub_range
from pmk_nb.raster import RasterOptions, plan_storey, rasterise_storey
from pmk_nb.witness import WITNESS_KEY, WitnessReport, witness_grid

if TYPE_CHECKING:
    from pmk_nb.indoorgml import Building
    from pmk_nb.rosmap import MapFiles

__all__ = ["ConvertOptions", "ConvertResult", "StoreyMap", "convert_plan"]

_READ_END = 0.3  # share of the progress bar for reading the plan
_RASTER_END = 0.9  # ... and for rasterising every storey; the rest is writing


@dataclass(frozen=True)
class ConvertOptions:
    """What to convert and how: one value that passes whole from ``pmk convert``, ``pmk maps convert``, the
    Maps screen and :meth:`~pmk_nb.library.folder.MapsFolder.convert_with` to the rasteriser, the openings
    plan and the accessibility check. Every default is :mod:`pmk_nb.defaults`'s."""

    resolution: float = DEFAULT_RESOLUTION  # metres per cell
    unit: str = "auto"
    crs: str = "auto"  # the coordinates' frame: auto, local, or a CRS name (see pmk_nb.indoorgml.crs)
    storeys: Sequence[str] | None = None
    wall_thickness: float = DEFAULT_WALL_THICKNESS
    max_wall_gap: float = DEFAULT_MAX_WALL_GAP
    outside: str = "unknown"
    image_format: str = "pgm"
    preview: bool = True
    max_cells: int = DEFAULT_MAX_CELLS
    allow_large: bool = False
    door_width: float = DEFAULT_DOOR_WIDTH  # metres: openings made where the file gives no door geometry
    chair_width: float = DEFAULT_CHAIR_WIDTH  # metres: the accessibility check's chair
    check: bool = True  # run the accessibility check and keep its report in the rooms file
    not_windows: tuple[str, ...] = ()  # cells (ids or names) the window/sill rule must leave navigable
    layers: tuple[str, ...] = ()  # space layers (ids or names) to draw instead of the navigable one

    @property
    def raster(self) -> RasterOptions:
        """The rasteriser's share of these options, passed whole to ``rasterise_storey``."""
        return RasterOptions(
            wall_thickness=self.wall_thickness,
            max_wall_gap=self.max_wall_gap,
            door_width=self.door_width,
            outside=self.outside,
            max_cells=self.max_cells,
            allow_large=self.allow_large,
        )


@dataclass(frozen=True)
class StoreyMap:
    """One storey's written map set (with its rooms file), its grid size and accessibility report."""

    storey: str
    files: MapFiles
    width: int
    height: int
    resolution: float
    rooms: Path | None = None
    access: StoreyReport | None = None
    witness: WitnessReport | None = None  # the written files judged against the plan (pmk_nb.witness)

    @property
    def size_m(self) -> tuple[float, float]:
        return self.width * self.resolution, self.height * self.resolution


@dataclass(frozen=True)
class ConvertResult:
    """What :func:`convert_plan` did: the building it read, the maps it wrote and every storey's stem."""

    building: Building
    maps: list[StoreyMap]
    stems: dict[str, str]  # file stem of every storey of the building, converted or not


def _check_options(opts: ConvertOptions) -> float:
    """Refuse bad numbers before the (possibly slow) read; returns the resolution as a float."""
    for label, value, positive in (
        ("resolution", opts.resolution, True),
        ("wall thickness", opts.wall_thickness, False),
        ("max wall gap", opts.max_wall_gap, False),
        ("door width", opts.door_width, True),
    ):
        ok = isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
        if not ok or value < 0 or (positive and value == 0):
            need = "a positive" if positive else "a non-negative"
            raise OccupancyError(f"{label} must be {need} number of metres, got {value!r}")
    if opts.image_format not in ("pgm", "png"):
        raise MapFormatError(f"image format must be 'pgm' or 'png', got {opts.image_format!r}")
    if opts.outside not in ("unknown", "occupied"):
        raise OccupancyError(f"outside must be 'unknown' or 'occupied', got {opts.outside!r}")
    check_chair_width(opts.chair_width)
    return float(opts.resolution)


def _wanted_storeys(building: Building, storeys: Sequence[str] | None) -> list[str]:
    wanted = list(dict.fromkeys(storeys)) if storeys else [s.name for s in building.storeys]
    for name in wanted:
        building.storey(name)  # IndoorGMLError naming the known storeys
    return wanted


def _stage_storeys(
    building: Building,
    wanted: list[str],
    stems: dict[str, str],
    opts: ConvertOptions,
    staging: Path,
    extra_meta: Mapping[str, Any],
    progress: ProgressCallback | None,
) -> list[StoreyMap]:
    """Rasterise and write every wanted storey into ``staging``; returns the maps (paths in staging)."""
    from pmk_nb.rosmap import write_map

    resolution = opts.resolution
    for storey in wanted:  # every storey's size is checked before anything is rasterised
        plan_storey(building, storey, resolution, opts.raster)
    span = (_RASTER_END - _READ_END) / len(wanted)
    staged: list[StoreyMap] = []
    for i, storey in enumerate(wanted):
        start = _READ_END + span * i
        emit(progress, "rasterise", start, f"storey {storey}")
        plan = plan_openings(building, storey, door_width=opts.door_width, max_gap=opts.max_wall_gap)
        grid = rasterise_storey(
            building, storey, resolution, opts.raster, openings=plan, progress=sub_range(progress, start, start + span)
        )
        grid.meta.update(extra_meta)
        grid.meta.setdefault("source_path", str(Path(building.source).resolve()))  # the witness finds the plan
        files = write_map(
            grid,
            staging,
            stems[storey],
            image_format=opts.image_format,
            preview=opts.preview,
            allow_large=opts.allow_large,
        )
        report = None
        if opts.check:
            report = check_grid(
                building,
                storey,
                grid,
                chair_width=opts.chair_width,
                options=opts.raster,
                plan=plan,
            )
        width, height, cell = grid.width, grid.height, grid.resolution
        del grid  # one storey's grid in memory at a time
        witnessed = _witness(building, files.yaml, opts.chair_width, width * height) if opts.check else None
        rooms = sidecar_path(files.yaml)
        doc = sidecar_json(building, storey, plan, None if report is None else report.to_json())
        choices = ConvertChoices(opts.unit, tuple(opts.not_windows), tuple(opts.layers), opts.crs)
        doc[CHOICES_KEY] = choices.to_json()  # kept for the next time
        if witnessed is not None:
            doc[WITNESS_KEY] = witnessed.to_json()
        rooms.write_text(json.dumps(doc, ensure_ascii=False), encoding="utf-8")
        staged.append(StoreyMap(storey, files, width, height, cell, rooms, report, witnessed))
    return staged


def _witness(building: Building, yaml_path: Path, chair_width: float, pixels: int) -> WitnessReport:
    """The files just written, read back as a map server reads them, judged against the plan."""
    from pmk_nb.rosmap import read_map

    return witness_grid(building, read_map(yaml_path, max_pixels=pixels), chair_width=chair_width)


def _install(staged: list[StoreyMap], out_dir: Path) -> list[StoreyMap]:
    """Move the staged files into ``out_dir`` (images and previews first, YAMLs last): renamed, as the
    staging folder lies inside ``out_dir`` (a copy of a 100 M-cell map cost 0.9 s)."""
    from pmk_nb.rosmap import MapFiles

    data = [p for m in staged for p in (m.files.image, m.files.preview, m.rooms) if p is not None]
    yamls = [m.files.yaml for m in staged]
    contents: list[tuple[str, Content]] = [(p.name, p) for p in data + yamls]  # moved, not copied
    try:
        replace_all(out_dir, contents)
    except OSError as err:
        msg = f"cannot write the map files in {out_dir}: {err.strerror or err}"
        raise MapFormatError(msg, path=str(out_dir)) from err
    moved = []
    for m in staged:
        f = m.files
        preview = None if f.preview is None else out_dir / f.preview.name
        files = MapFiles(out_dir / f.yaml.name, out_dir / f.image.name, preview)
        rooms = None if m.rooms is None else out_dir / m.rooms.name
        moved.append(StoreyMap(m.storey, files, m.width, m.height, m.resolution, rooms, m.access, m.witness))
    return moved


def convert_plan(
    source: str | os.PathLike[str],
    out_dir: str | os.PathLike[str],
    name: str,
    resolution: float | None = None,
    options: ConvertOptions | None = None,
    *,
    extra_meta: Mapping[str, Any] | None = None,
    progress: ProgressCallback | None = None,
) -> ConvertResult:
    """Read the plan ``source``, rasterise its storeys and write ``NAME[_<storey>].yaml`` + image + preview.

    Args:
        source: the IndoorGML file.
        out_dir: the folder the map sets go to (created if missing).
        name: base name of the files (``NAME`` for a one-storey building, ``NAME_<storey>`` otherwise).
        resolution: metres per cell: ``options.resolution`` when None (given, it replaces that).
        options: what to convert and how (:class:`ConvertOptions`).
        extra_meta: keys added to every YAML (the maps folder names the map and its source there).
        progress: steps ``read``, ``rasterise``, ``write``, ``done``.

    Raises:
        IndoorGMLError: the plan cannot be read, or a storey name is unknown.
        OccupancyError: bad numbers; :class:`~pmk_nb.errors.GridTooLarge` for a storey over budget.
        MapFormatError: the files cannot be written (the folder is left as it was).
    """
    from pmk_nb.indoorgml import read_building

    opts = options or ConvertOptions()
    if resolution is not None:
        opts = replace(opts, resolution=resolution)
    opts = replace(opts, resolution=_check_options(opts))
    emit(progress, "read", 0.0, Path(source).name)
    building = read_building(
        source,
        unit=opts.unit,
        crs=opts.crs,
        progress=sub_range(progress, 0.0, _READ_END),
        not_windows=opts.not_windows,
        layers=opts.layers,
    )
    wanted = _wanted_storeys(building, opts.storeys)
    stems = storey_map_names(name, [s.name for s in building.storeys])
    target = Path(out_dir)
    try:
        target.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(prefix=f".{name}.convert-", dir=target))
    except OSError as err:
        raise MapFormatError(f"cannot create the map folder {target}: {err.strerror or err}", path=str(target)) from err
    try:
        staged = _stage_storeys(building, wanted, stems, opts, staging, extra_meta or {}, progress)
        emit(progress, "write", _RASTER_END + 0.05, f"{len(staged)} map set(s)")
        maps = _install(staged, target)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    emit(progress, "done", 1.0)
    return ConvertResult(building, maps, stems)
