"""`pmk check FILE_OR_MAP [--chair-width W] [--json]`: can a wheelchair go where the building's graph says?

Like a linter: exit 0 when every transition is passable for the chair and nothing leaks, 1 when the
check finds a problem (listed), 2 on bad input. A ``.gml`` file is rasterised in memory (nothing is
written); a map ``.yaml`` is checked as written, against the rooms file beside it.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import asdict
from pathlib import Path
from typing import Any

from pmk_nb.cli.convert import add_not_window_option
from pmk_nb.errors import PmkError


def add_parser(subparsers: Any) -> None:
    p = subparsers.add_parser(
        "check",
        help="wheelchair accessibility of a building plan or a written map (exit 1: problems found)",
        description="Check that a chair of the given width can pass every transition of the building's "
        "navigation graph, name doors narrower than the chair, rooms it cannot reach and rooms that leak "
        "into each other. Exit 0: all passable; 1: problems found; 2: bad input.",
    )
    p.add_argument("target", type=Path, help="an IndoorGML file (.gml) or a converted map (.yaml)")
    p.add_argument("--chair-width", type=float, default=None, metavar="W",
                   help="chair width in metres (default: the chair profile's, Settings; else 0.70)")  # fmt: skip
    p.add_argument("--resolution", "-r", type=float, default=0.05,
                   help="metres per cell when checking a .gml file (default 0.05)")  # fmt: skip
    p.add_argument("--unit", default="auto", help="unit of a .gml file's coordinates: auto (default), m, dm, cm, mm")
    p.add_argument("--door-width", type=float, default=None, metavar="M",
                   help="width of openings made where the file gives no door geometry (default 0.9)")  # fmt: skip
    add_not_window_option(p)
    p.add_argument("--json", action="store_true", help="print the report as JSON")
    p.set_defaults(run=run)


def chair_width_arg(given: float | None) -> float:
    """--chair-width when given, else the width in the last used chair profile (Settings), else 0.70 m."""
    from pmk_nb.access.check import profile_chair_width
    from pmk_nb.chair.profiles import ProfileStore

    profile = None
    if given is None:
        try:
            profile = ProfileStore(secrets=False).last_used()
        except (PmkError, OSError, ValueError):  # an unreadable profile file: the default chair
            profile = None
    return profile_chair_width(given, profile)


def _reports(args: argparse.Namespace) -> tuple[list[Any], str, Any]:
    """The storeys' reports, the unit conflict and the unit suspect (a plan's; a written map has none)."""
    from pmk_nb.access.check import check_building, check_map
    from pmk_nb.raster.openings import DEFAULT_DOOR_WIDTH

    target: Path = args.target
    width = chair_width_arg(args.chair_width)
    if target.is_dir():
        raise PmkError(f"{target} is a folder", hint="Name an IndoorGML file (.gml) or a map YAML (.yaml).")
    if not target.is_file():
        raise PmkError(f"{target}: no such file", hint="Name an IndoorGML file (.gml) or a map YAML (.yaml).")
    if target.suffix.lower() in (".yaml", ".yml"):
        if args.not_windows:
            raise PmkError(f"{target}: --not-window applies to a plan (.gml), not to a written map",
                           hint="Convert the plan again with --not-window, then check the new map.")  # fmt: skip
        return [check_map(target, chair_width=width)], "", None
    from pmk_nb.indoorgml import read_building

    building = read_building(target, unit=args.unit, not_windows=args.not_windows)
    door = DEFAULT_DOOR_WIDTH if args.door_width is None else args.door_width
    reports = check_building(building, args.resolution, chair_width=width, door_width=door)
    return reports, building.unit_conflict, building.unit_suspect


MAX_NOT_CHECKED = 10  # transitions named per storey; the rest are counted
WINDOW_HINT = [
    "note: a cell is judged a window/sill when it starts more than {raised:g} m above a cell it touches.",
    "  If one named above is really a door or floor, the rule misjudged it and its transitions went",
    "  unchecked: convert (and check) the plan again with --not-window NAME to keep it navigable.",
]


def format_report(reports: list[Any], unit_conflict: str = "", unit_suspect: Any = None) -> list[str]:
    """The text report: the unit first when the doors are absurd in it (see units.unit_suspect: no door
    is to blame then), one summary line per storey, then each problem by name, then the transitions
    it could not check (windows: a misjudged one hides a door, so they are named, not only counted)."""
    from pmk_nb.indoorgml.levels import RAISED
    from pmk_nb.raster.openings import SKIP_WINDOW

    lines = [f"suspect the unit first: {unit_suspect.message}"] if unit_suspect is not None else []
    for r in reports:
        lines.append(r.summary())
        lines.extend(f"  blocked: {k.describe()}" for k in r.blocked)
        lines.extend(f"  unreachable: {name}" for name in r.unreachable)
        lines.extend(f"  leak: {a} and {b} are joined in the map but not in the graph" for a, b in
                     (leak.names for leak in r.leaks))  # fmt: skip
        lines.extend(f"  not checked: {k.describe()}" for k in r.not_checked[:MAX_NOT_CHECKED])
        if len(r.not_checked) > MAX_NOT_CHECKED:
            lines.append(f"  not checked: and {len(r.not_checked) - MAX_NOT_CHECKED} more (--json lists them all)")
    if any(k.reason == SKIP_WINDOW for r in reports for k in r.not_checked):
        lines.extend(line.format(raised=RAISED) for line in WINDOW_HINT)
    if unit_conflict:
        lines.append(f"unit warning: {unit_conflict}")
    return lines


def run(args: argparse.Namespace) -> int:
    reports, conflict, suspect = _reports(args)
    ok = all(r.ok for r in reports)
    if args.json:
        doc = {"ok": ok, "unit_conflict": conflict, "unit_suspect": None if suspect is None else asdict(suspect),
               "storeys": [r.to_json() for r in reports]}  # fmt: skip
        json.dump(doc, sys.stdout, indent=2, ensure_ascii=False)
        sys.stdout.write("\n")
    else:
        print("\n".join(format_report(reports, conflict, suspect)))
        skipped = sum(len(r.not_checked) for r in reports)
        said = f"every transition checked ({skipped} not checked, above)" if skipped else "everywhere the graph says"
        print(f"ok: the chair can pass {said}" if ok else "problems found")
    return 0 if ok else 1
