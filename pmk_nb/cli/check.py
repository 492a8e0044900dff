"""`pmk check FILE_OR_MAP [--chair-width W] [--json]`: can a wheelchair go where the building's graph says?

Like a linter: exit 0 when every transition is passable for the chair and nothing leaks, 1 when the
check finds a problem (listed), 2 on bad input, 3 when nothing could be checked (see EXIT_CODES). A
``.gml`` file is rasterised in memory (nothing is written); a map ``.yaml`` is checked as written,
against the rooms file beside it.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from pmk_nb.cli.options import (
    Subparsers,
    add_crs_option,
    add_json,
    add_layer_option,
    add_not_window_option,
    add_resolution,
    chair_width_arg,
)
from pmk_nb.errors import PmkError

if TYPE_CHECKING:
    from pmk_nb.access import StoreyReport
    from pmk_nb.grid import OccupancyGrid
    from pmk_nb.indoorgml import Building, UnitSuspect
    from pmk_nb.witness import WitnessReport

EXIT_OK, EXIT_PROBLEMS, EXIT_NOTHING_CHECKED = 0, 1, 3  # 2: bad input (every PmkError, cli/__init__)
EXIT_CODES = (
    "Exit codes: 0 = every transition checked is passable for the chair; 1 = problems found (listed); "
    "2 = bad input (unreadable plan or map, unknown layer or option); 3 = nothing could be checked on a "
    "storey or the whole plan: its navigation graph is absent, or lost (its transitions name states that "
    "are not in the file), or gives no transition on that storey (said why, never reported ok)"
)


def add_parser(subparsers: Subparsers) -> None:
    p = subparsers.add_parser(
        "check",
        help="wheelchair accessibility of a building plan or a written map (exit 1: problems, 3: nothing checked)",
        description="Check that a chair of the given width can pass every transition of the building's "
        "navigation graph, name doors narrower than the chair, rooms it cannot reach and rooms that leak "
        "into each other. " + EXIT_CODES + ".",
    )
    p.add_argument("target", type=Path, help="an IndoorGML file (.gml) or a converted map (.yaml)")
    p.add_argument(
        "--chair-width",
        type=float,
        default=None,
        metavar="W",
        help="chair width in metres (default: the chair profile's, Settings; else 0.70)",
    )
    add_resolution(p, what="metres per cell when checking a .gml file")
    p.add_argument("--unit", default="auto", help="unit of a .gml file's coordinates: auto (default), m, dm, cm, mm")
    add_crs_option(p)
    p.add_argument(
        "--door-width",
        type=float,
        default=None,
        metavar="M",
        help="width of openings made where the file gives no door geometry (default 0.9)",
    )
    p.add_argument(
        "--plan",
        type=Path,
        default=None,
        metavar="FILE",
        help="for a map (.yaml): the plan it was converted from (default: the plan its YAML names, "
        "found as written, from the map's folder or beside the map)",
    )
    p.add_argument(
        "--picture",
        type=Path,
        default=None,
        metavar="FILE",
        help="write a PNG of the map with the witness's findings ringed and numbered "
        "(FILE_<storey>.png per storey when there are several)",
    )
    add_not_window_option(p)
    add_layer_option(p)
    add_json(p, "the report")
    p.set_defaults(run=run)


@dataclass
class Witnessed:
    """The witness's reports (one per storey) with the grids they judged, or why it could not run."""

    reports: list[WitnessReport] = field(default_factory=list)
    grids: list[OccupancyGrid] = field(default_factory=list)
    missing: str = ""  # why the witness could not run ('' when it ran)

    @property
    def findings(self) -> int:
        return sum(len(r.findings) for r in self.reports)

    @property
    def complete(self) -> bool:
        return not self.missing and bool(self.reports) and all(r.graph for r in self.reports)


def _reports(args: argparse.Namespace) -> tuple[list[StoreyReport], Building | None, Witnessed]:
    """The storeys' reports, the plan's Building (None for a written map: its rooms file says the
    rest) and the witness's verdict on the same grids."""
    from pmk_nb.access import check_building, check_map
    from pmk_nb.raster import RasterOptions
    from pmk_nb.witness import PlanNotFound, witness_grid, witness_map

    target: Path = args.target
    width = chair_width_arg(args.chair_width)
    if target.is_dir():
        raise PmkError(f"{target} is a folder", hint="Name an IndoorGML file (.gml) or a map YAML (.yaml).")
    if not target.is_file():
        raise PmkError(f"{target}: no such file", hint="Name an IndoorGML file (.gml) or a map YAML (.yaml).")
    witnessed = Witnessed()
    if target.suffix.lower() in (".yaml", ".yml"):
        if args.not_windows or args.layers:
            opt = "--not-window" if args.not_windows else "--layer"
            raise PmkError(
                f"{target}: {opt} applies to a plan (.gml), not to a written map",
                hint=f"Convert the plan again with {opt}, then check the new map.",
            )
        report = check_map(target, chair_width=width)
        try:
            verdict, grid = witness_map(target, chair_width=width, plan=args.plan)
            witnessed.reports.append(verdict)
            witnessed.grids.append(grid)
        except PlanNotFound as err:
            witnessed.missing = str(err)
        return [report], None, witnessed
    from pmk_nb.indoorgml import read_building

    building = read_building(target, unit=args.unit, not_windows=args.not_windows, layers=args.layers, crs=args.crs)
    options = RasterOptions() if args.door_width is None else RasterOptions(door_width=args.door_width)

    def judge(storey: str, grid: OccupancyGrid) -> None:
        witnessed.reports.append(witness_grid(building, grid, chair_width=width))
        if args.picture is not None:
            witnessed.grids.append(grid)

    reports = check_building(building, args.resolution, chair_width=width, options=options, on_grid=judge)
    return reports, building, witnessed


MAX_NOT_CHECKED = 10  # transitions named per storey; the rest are counted
WINDOW_HINT = [
    "note: a cell is judged a window/sill when it starts more than {raised:g} m above a cell it touches.",
    "  If one named above is really a door or floor, the rule misjudged it and its transitions went",
    "  unchecked: convert (and check) the plan again with --not-window NAME to keep it navigable.",
]


def format_report(
    reports: list[StoreyReport], unit_conflict: str = "", unit_suspect: UnitSuspect | None = None
) -> list[str]:
    """The text report: the unit first when the doors are absurd in it (see units.unit_suspect: no door
    is to blame then), one summary line per storey, then each problem by name, then the transitions
    it could not check (windows: a misjudged one hides a door, so they are named, not only counted)."""
    from pmk_nb.indoorgml import RAISED
    from pmk_nb.openings import SKIP_WINDOW

    lines = [f"suspect the unit first: {unit_suspect.message}"] if unit_suspect is not None else []
    for r in reports:
        lines.append(r.summary())
        lines.extend(f"  blocked: {k.describe()}" for k in r.blocked)
        lines.extend(f"  unreachable: {name}" for name in r.unreachable)
        lines.extend(
            f"  leak: {a} and {b} are joined in the map but not in the graph"
            for a, b in (leak.names for leak in r.leaks)
        )
        lines.extend(f"  not checked: {k.describe()}" for k in r.not_checked[:MAX_NOT_CHECKED])
        if len(r.not_checked) > MAX_NOT_CHECKED:
            lines.append(f"  not checked: and {len(r.not_checked) - MAX_NOT_CHECKED} more (--json lists them all)")
    if any(k.reason == SKIP_WINDOW for r in reports for k in r.not_checked):
        lines.extend(line.format(raised=RAISED) for line in WINDOW_HINT)
    if unit_conflict:
        lines.append(f"unit warning: {unit_conflict}")
    return lines


def exit_code(reports: list[StoreyReport], witnessed: Witnessed | None = None) -> int:
    """1 when a checked storey has a problem or the witness finds the map disagrees with the plan; else 3
    when a storey (or the plan) could not be checked, or the witness could not judge it; else 0."""
    if any(r.checked and not r.ok for r in reports) or (witnessed is not None and witnessed.findings):
        return EXIT_PROBLEMS
    if witnessed is not None and not witnessed.complete:
        return EXIT_NOTHING_CHECKED
    return EXIT_OK if reports and all(r.checked for r in reports) else EXIT_NOTHING_CHECKED


def verdict(reports: list[StoreyReport], code: int, witnessed: Witnessed | None = None) -> str:
    """The last line: what the exit code means for this plan."""
    if code == EXIT_PROBLEMS:
        return "problems found"
    if code == EXIT_NOTHING_CHECKED and witnessed is not None and witnessed.missing:
        return "not checked (exit 3): the witness could not judge the map against its plan; see above"
    if code == EXIT_NOTHING_CHECKED:
        names = ", ".join(r.storey for r in reports if not r.checked) or "-"
        return f"not checked (exit 3): nothing could be checked on storey(s) {names}; see above"
    skipped = sum(len(r.not_checked) for r in reports)
    said = f"every transition checked ({skipped} not checked, above)" if skipped else "everywhere the graph says"
    return f"ok: the chair can pass {said}, and the written map agrees with the plan"


def witness_lines(witnessed: Witnessed) -> list[str]:
    """The witness's part of the text report: each storey's verdict, then its findings, numbered as in
    the picture."""
    if witnessed.missing:
        return [f"witness: not run: {witnessed.missing}"]
    lines = []
    for r in witnessed.reports:
        lines.append(r.summary())
        lines.extend(f"  {n}. {f.describe()}" for n, f in enumerate(r.findings, 1))
    return lines


def _pictures(path: Path, witnessed: Witnessed) -> list[Path]:
    """Write the witness's picture per storey: ``path`` itself for one storey, ``path_<storey>.png`` else."""
    from pmk_nb.witness import write_picture

    written = []
    several = len(witnessed.reports) > 1
    for report, grid in zip(witnessed.reports, witnessed.grids, strict=True):
        out = path.with_name(f"{path.stem}_{report.storey}{path.suffix or '.png'}") if several else path
        write_picture(out, grid, report.findings)
        written.append(out)
    return written


def run(args: argparse.Namespace) -> int:
    from pmk_nb.indoorgml import graph_lines, layer_lines

    reports, building, witnessed = _reports(args)
    code = exit_code(reports, witnessed)
    conflict = building.unit_conflict if building is not None else ""
    suspect = building.unit_suspect if building is not None else None
    pictures = [] if args.picture is None or witnessed.missing else _pictures(args.picture, witnessed)
    if args.json:
        doc = {
            "ok": code == EXIT_OK,
            "exit_code": code,
            "unit_conflict": conflict,
            "unit_suspect": None if suspect is None else asdict(suspect),
            "graph": None if building is None else building.graph_status.to_json(),
            "skipped_layers": [] if building is None else [asdict(n) for n in building.skipped_layers],
            "storeys": [r.to_json() for r in reports],
            "witness": {
                "ran": not witnessed.missing,
                "reason": witnessed.missing,
                "storeys": [r.to_json() for r in witnessed.reports],
                "pictures": [str(p) for p in pictures],
            },
        }
        json.dump(doc, sys.stdout, indent=2, ensure_ascii=False)
        sys.stdout.write("\n")
    else:
        head = (
            []
            if building is None
            else [
                *graph_lines(building.graph_status.to_json()),
                *layer_lines([asdict(n) for n in building.skipped_layers]),
            ]
        )
        print("\n".join(head + format_report(reports, conflict, suspect) + witness_lines(witnessed)))
        for picture in pictures:
            print(f"picture: {picture}")
        print(verdict(reports, code, witnessed))
    return code
