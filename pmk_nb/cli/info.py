"""`pmk info FILE [--unit U] [--json]`: what the IndoorGML reader makes of a building plan."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    from pmk_nb.indoorgml.units import UNIT_CHOICES

    p = subparsers.add_parser(
        "info",
        help="summarise an IndoorGML file (storeys, cells, doors, units, georeference)",
        description="Read an IndoorGML file and print its storeys, cells, doors, units and warnings.",
    )
    p.add_argument("file", help="IndoorGML (.gml) file")
    p.add_argument("--unit", default="auto", choices=UNIT_CHOICES,
                   help="coordinate unit of the file (default: auto-detect, see the reason printed)")  # fmt: skip
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.set_defaults(run=run)
    return p


def run(args: argparse.Namespace) -> int:
    from pmk_nb.indoorgml import format_summary, read_building, summarize

    summary = summarize(read_building(args.file, unit=args.unit))
    if args.json:
        json.dump(summary, sys.stdout, indent=2, ensure_ascii=False)
        sys.stdout.write("\n")
    else:
        print(format_summary(summary))
    return 0
