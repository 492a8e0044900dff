"""`pmk convert FILE --resolution R`: IndoorGML -> one map_server set (YAML + image + preview) per storey.

Everything that can fail on bad input (parsing, unit, storey names, the size budget of every storey)
is checked before the first file is written; each storey's set is then written atomically.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import TextIO

from pmk_nb.errors import OccupancyError

_BIG_FILE = 5 * 1024 * 1024  # show a progress bar for files above this size (or on a terminal)


class TextProgress:
    """A one-line text progress bar on a stream, redrawn at most every ``interval`` seconds."""

    def __init__(self, stream: TextIO, label: str, *, enabled: bool = True, interval: float = 0.2) -> None:
        self.stream, self.label, self.enabled, self.interval = stream, label, enabled, interval
        self._last = 0.0
        self._shown = False

    def stage(self, label: str) -> None:
        self.label = label
        self._last = 0.0

    def __call__(self, done: int, total: int) -> None:
        if not self.enabled:
            return
        now = time.monotonic()
        if done < total and now - self._last < self.interval:
            return
        self._last = now
        frac = 0.0 if total <= 0 else min(1.0, done / total)
        bar = "#" * int(frac * 30)
        self.stream.write(f"\r{self.label:<24} [{bar:<30}] {frac * 100:5.1f}%")
        self.stream.flush()
        self._shown = True

    def close(self) -> None:
        if self._shown:
            self.stream.write("\n")
            self.stream.flush()
            self._shown = False


def add_parser(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = subparsers.add_parser(
        "convert",
        help="convert an IndoorGML file to ROS map_server maps (one set per storey)",
        description="Rasterise each storey of an IndoorGML building at RESOLUTION m/cell and write "
        "NAME.yaml + NAME.pgm + NAME-visualization.png (NAME_<storey>.* when there are several storeys).",
    )
    p.add_argument("file", type=Path, help="the IndoorGML (.gml) file")
    p.add_argument("--resolution", "-r", type=float, required=True, help="metres per cell, e.g. 0.05")
    p.add_argument("--storey", action="append", dest="storeys", metavar="S", help="only this storey (repeatable)")
    p.add_argument("--out", type=Path, default=None, help="output folder (default: the file's folder)")
    p.add_argument("--name", default=None, help="base name of the map files (default: the file's stem)")
    p.add_argument("--wall-thickness", type=float, default=0.10, help="wall band in metres (default 0.10)")
    p.add_argument(
        "--max-wall-gap", type=float, default=0.5, metavar="M",
        help="gaps between cells up to M metres wide are walls the file left out: occupied (default 0.5, 0 = off)",
    )  # fmt: skip
    p.add_argument("--unit", default="auto", help="coordinate unit: auto, m, dm, cm, mm (default auto)")
    p.add_argument("--format", choices=("pgm", "png"), default="pgm", dest="image_format", help="map image format")
    p.add_argument("--outside", choices=("unknown", "occupied"), default="unknown", help="value outside all cells")
    p.add_argument("--no-preview", action="store_true", help="skip NAME-visualization.png")
    p.add_argument("--max-cells", type=int, default=None, help="refuse grids with more cells than this")
    p.add_argument("--allow-large", action="store_true", help="allow grids over 32767 cells per side (not Nav2)")
    bar = p.add_mutually_exclusive_group()
    bar.add_argument("--progress", dest="progress", action="store_true", default=None, help="always show progress")
    bar.add_argument("--no-progress", dest="progress", action="store_false", help="never show progress")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from pmk_nb.indoorgml import read_building
    from pmk_nb.library.naming import safe_file_part, storey_map_names
    from pmk_nb.raster.storey import DEFAULT_MAX_CELLS, plan_storey, rasterise_storey
    from pmk_nb.rosmap.files import write_map

    path: Path = args.file
    out_dir: Path = args.out if args.out is not None else path.parent
    base = safe_file_part(args.name if args.name else path.stem)
    show = args.progress
    if show is None:
        size = path.stat().st_size if path.is_file() else 0
        show = sys.stderr.isatty() or size > _BIG_FILE
    bar = TextProgress(sys.stderr, "reading", enabled=bool(show))
    try:
        building = read_building(path, unit=args.unit, progress=bar)
        bar.close()
        names = [s.name for s in building.storeys]
        storeys = list(dict.fromkeys(args.storeys)) if args.storeys else names
        unknown = [s for s in storeys if s not in names]
        if unknown:
            raise OccupancyError(
                f"{path}: no storey named {', '.join(map(repr, unknown))}; storeys are: {', '.join(names)}"
            )
        kw = {
            "wall_thickness": args.wall_thickness,
            "max_cells": args.max_cells or DEFAULT_MAX_CELLS,
            "allow_large": args.allow_large,
        }
        for storey in storeys:  # every storey's size is checked before anything is written
            plan_storey(building, storey, args.resolution, **kw)
        file_names = storey_map_names(base, storeys, several=len(names) > 1)
        print(f"{path}: unit {building.unit} ({building.unit_reason}); {len(storeys)} storey(s)")
        for storey in storeys:
            bar.stage(f"storey {storey}")
            grid = rasterise_storey(
                building, storey, args.resolution, outside=args.outside, max_wall_gap=args.max_wall_gap,
                progress=bar, **kw,
            )  # fmt: skip
            bar.close()
            files = write_map(
                grid, out_dir, file_names[storey], image_format=args.image_format,
                preview=not args.no_preview, allow_large=args.allow_large,
            )  # fmt: skip
            w_m, h_m = grid.size_m
            extra = f", {files.preview.name}" if files.preview else ""
            print(
                f"  storey {storey}: {files.yaml} (+ {files.image.name}{extra}) "
                f"{grid.width} x {grid.height} cells = {w_m:.2f} x {h_m:.2f} m at {grid.resolution:g} m/cell"
            )
    finally:
        bar.close()
    return 0
