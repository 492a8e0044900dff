"""`pmk convert FILE --resolution R`: IndoorGML -> one map_server set (YAML + image + preview) per storey.

The work is :func:`pmk_nb.library.convert.convert_plan`, the same pipeline the Maps screen runs:
everything that can fail on bad input (parsing, unit, storey names, the size budget of every
storey) fails before the first file is written, and the sets are written all or nothing.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

from pmk_nb.cli.options import (
    Subparsers,
    add_crs_option,
    add_json,
    add_layer_option,
    add_not_window_option,
    add_resolution,
    chair_width_arg,
    print_json,
)
from pmk_nb.defaults import (
    DEFAULT_CHAIR_WIDTH,
    DEFAULT_DOOR_WIDTH,
    DEFAULT_MAX_CELLS,
    DEFAULT_MAX_WALL_GAP,
    DEFAULT_WALL_THICKNESS,
)
from pmk_nb.errors import GridTooLarge, PmkError
from pmk_nb.progress import Progress

if TYPE_CHECKING:
    from pmk_nb.library import ConvertResult

_BIG_FILE = 5 * 1024 * 1024  # show a progress bar for files above this size (or on a terminal)


class TextProgress:
    """A one-line text progress bar on a stream, redrawn at most every ``interval`` seconds."""

    def __init__(self, stream: TextIO, *, enabled: bool = True, interval: float = 0.2) -> None:
        self.stream, self.enabled, self.interval = stream, enabled, interval
        self._last = 0.0
        self._shown = False

    def __call__(self, p: Progress) -> None:
        if not self.enabled:
            return
        now = time.monotonic()
        frac = p.fraction or 0.0
        if frac < 1.0 and now - self._last < self.interval:
            return
        self._last = now
        bar = "#" * int(frac * 30)
        label = f"{p.step} {p.message}".strip()[:24]
        self.stream.write(f"\r{label:<24} [{bar:<30}] {frac * 100:5.1f}%")
        self.stream.flush()
        self._shown = True

    def close(self) -> None:
        if self._shown:
            self.stream.write("\n")
            self.stream.flush()
            self._shown = False


def add_raster_options(p: argparse.ArgumentParser) -> None:
    """The rasterising options `pmk convert` and `pmk maps convert` share (one wording for both)."""
    p.add_argument(
        "--wall-thickness",
        type=float,
        default=DEFAULT_WALL_THICKNESS,
        help=f"wall band in metres (default {DEFAULT_WALL_THICKNESS:.2f})",
    )
    p.add_argument(
        "--max-wall-gap",
        type=float,
        default=DEFAULT_MAX_WALL_GAP,
        metavar="M",
        help="walls the file left out as gaps: a door or transition opens one up to M metres wide; a gap no"
        f" transition crosses is wall up to the thickest wall, at least max(M, 1 m) (default {DEFAULT_MAX_WALL_GAP:g},"
        " 0 = off)",
    )
    # no argparse choices: they live in pmk_nb.indoorgml, too heavy to import for every `pmk` call
    p.add_argument("--unit", default="auto", help="unit of the file's coordinates: auto (default), m, dm, cm, mm")
    add_crs_option(p)
    p.add_argument("--format", choices=("pgm", "png"), default="pgm", dest="image_format", help="map image format")
    p.add_argument(
        "--door-width",
        type=float,
        default=DEFAULT_DOOR_WIDTH,
        metavar="M",
        help=f"width of openings made where the file gives no door geometry (default {DEFAULT_DOOR_WIDTH:g})",
    )
    p.add_argument(
        "--chair-width",
        type=float,
        default=None,
        metavar="W",
        help=f"chair width for the access summary (default: the chair profile's, or {DEFAULT_CHAIR_WIDTH:.2f})",
    )
    add_not_window_option(p)
    add_layer_option(p)


def add_parser(subparsers: Subparsers) -> None:
    p = subparsers.add_parser(
        "convert",
        help="convert an IndoorGML file to ROS map_server maps (one set per storey)",
        description="Rasterise each storey of an IndoorGML building at RESOLUTION m/cell and write "
        "NAME.yaml + NAME.pgm + NAME-visualization.png (NAME_<storey>.* when there are several storeys).",
    )
    p.add_argument("file", type=Path, help="the IndoorGML (.gml) file")
    add_resolution(p)
    p.add_argument("--storey", action="append", dest="storeys", metavar="S", help="only this storey (repeatable)")
    p.add_argument("--out", type=Path, default=Path("."), help="output folder (default: the current folder)")
    p.add_argument("--name", default=None, help="base name of the map files (default: the file's stem)")
    add_raster_options(p)
    p.add_argument("--outside", choices=("unknown", "occupied"), default="unknown", help="value outside all cells")
    p.add_argument("--no-preview", action="store_true", help="skip NAME-visualization.png")
    p.add_argument("--max-cells", type=int, default=None, help="refuse grids with more cells than this")
    p.add_argument("--allow-large", action="store_true", help="allow grids over 32767 cells per side (not Nav2)")
    add_json(p, "what was written (building, unit, storeys: files, size, accessibility)")
    bar = p.add_mutually_exclusive_group()
    bar.add_argument("--progress", dest="progress", action="store_true", default=None, help="always show progress")
    bar.add_argument("--no-progress", dest="progress", action="store_false", help="never show progress")
    p.set_defaults(run=run)


MAX_FINDINGS = 5  # the witness's findings printed per storey; `pmk check` lists them all


def result_json(path: Path, result: ConvertResult) -> dict[str, Any]:
    """`pmk convert --json`: the files written per storey and each storey's access verdict."""
    from dataclasses import asdict

    building = result.building
    storeys = []
    for m in result.maps:
        files = m.files
        storeys.append(
            {
                "storey": m.storey,
                "yaml": str(files.yaml),
                "image": str(files.image),
                "preview": None if files.preview is None else str(files.preview),
                "rooms": None if m.rooms is None else str(m.rooms),
                "width": m.width,
                "height": m.height,
                "resolution": m.resolution,
                "access": None if m.access is None else m.access.to_json(),
                "witness": None if m.witness is None else m.witness.to_json(),
            }
        )
    return {
        "ok": True,
        "file": str(path),
        "unit": building.unit,
        "unit_reason": building.unit_reason,
        "unit_conflict": building.unit_conflict or None,
        "unit_votes": [asdict(v) for v in building.unit_votes],
        "unit_suspect": None if building.unit_suspect is None else asdict(building.unit_suspect),
        "graph": building.graph_status.to_json(),
        "overlaps": [asdict(o) for o in building.overlaps],
        "storeys": storeys,
    }


def run(args: argparse.Namespace) -> int:
    from pmk_nb.library import ConvertOptions, convert_plan, safe_file_part

    path: Path = args.file
    if path.is_dir():
        raise PmkError(f"{path} is a folder, not a building plan", hint="Name one IndoorGML (.gml) file to convert.")
    show = args.progress
    if show is None:
        size = path.stat().st_size if path.is_file() else 0
        show = sys.stderr.isatty() or size > _BIG_FILE
    options = ConvertOptions(
        resolution=args.resolution,
        unit=args.unit,
        crs=args.crs,
        storeys=args.storeys,
        wall_thickness=args.wall_thickness,
        max_wall_gap=args.max_wall_gap,
        outside=args.outside,
        image_format=args.image_format,
        preview=not args.no_preview,
        max_cells=args.max_cells or DEFAULT_MAX_CELLS,
        allow_large=args.allow_large,
        door_width=args.door_width,
        chair_width=chair_width_arg(args.chair_width),
        not_windows=tuple(args.not_windows),
        layers=tuple(args.layers),
    )
    bar = TextProgress(sys.stderr, enabled=bool(show))
    try:
        result = convert_plan(
            path,
            args.out,
            safe_file_part(args.name or path.stem),
            None,
            options,
            progress=bar,
        )
    except GridTooLarge as err:  # the CLI's words for the way out: the option to change
        raise PmkError(err.message, hint=f"Use --resolution {err.suggested_resolution:g} or coarser.") from err
    finally:
        bar.close()
    if args.json:
        print_json(result_json(path, result))
        return 0
    building = result.building
    print(f"{path}: unit {building.unit} ({building.unit_reason}); {len(result.maps)} storey(s)")
    from dataclasses import asdict

    from pmk_nb.indoorgml import graph_lines, layer_lines, overlap_lines

    for line in (
        graph_lines(building.graph_status.to_json())
        + layer_lines(list(map(asdict, building.skipped_layers)))
        + overlap_lines(list(map(asdict, building.overlaps)))
    ):
        print(line)
    for m in result.maps:
        w_m, h_m = m.size_m
        extra = f", {m.files.preview.name}" if m.files.preview else ""
        print(
            f"  storey {m.storey}: {m.files.yaml} (+ {m.files.image.name}{extra}) "
            f"{m.width} x {m.height} cells = {w_m:.2f} x {h_m:.2f} m at {m.resolution:g} m/cell"
        )
        if m.access is not None:
            print(f"    accessibility: {m.access.summary().split(': ', 1)[1]}")
        if m.witness is not None:
            print(f"    {m.witness.summary()}")
            for finding in m.witness.findings[:MAX_FINDINGS]:
                print(f"      {finding.describe()}")
            if len(m.witness.findings) > MAX_FINDINGS:
                print(f"      and {len(m.witness.findings) - MAX_FINDINGS} more (pmk check MAP.yaml lists them all)")
    if building.unit_conflict:
        print(f"  unit warning: {building.unit_conflict} (--unit m|dm|cm|mm)")
    if building.unit_suspect is not None:  # absurd doors: the unit before any door
        print(f"  unit suspect: {building.unit_suspect.message}")
    problems = [m for m in result.maps if m.access is not None and (not m.access.ok or m.access.not_checked)]
    problems += [m for m in result.maps if m.witness is not None and m.witness.findings]
    if problems:
        print(f"  details: pmk check {result.maps[0].files.yaml.parent}/<map>.yaml  (or pmk check {path})")
    return 0
