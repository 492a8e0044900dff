"""`pmk info FILE [--unit U] [--json]`: what the IndoorGML reader makes of a building plan."""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import asdict
from typing import TYPE_CHECKING, Any

from pmk_nb.cli.options import Subparsers, add_crs_option, add_layer_option, add_not_window_option

if TYPE_CHECKING:
    from pmk_nb.indoorgml import Building


def add_parser(subparsers: Subparsers) -> argparse.ArgumentParser:
    from pmk_nb.indoorgml import UNIT_CHOICES

    p = subparsers.add_parser(
        "info",
        help="summarise an IndoorGML file (storeys, cells, doors, units, georeference)",
        description="Read an IndoorGML file and print its storeys, cells, doors, units and warnings.",
    )
    p.add_argument("file", help="IndoorGML (.gml) file")
    p.add_argument(
        "--unit",
        default="auto",
        choices=UNIT_CHOICES,
        help="coordinate unit of the file (default: auto-detect, see the reason printed)",
    )
    add_crs_option(p)
    add_not_window_option(p)
    add_layer_option(p)
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.set_defaults(run=run)
    return p


def connectivity(building: Building) -> dict[str, Any]:
    """How the navigation graph will open the walls: links, and the rule used per storey (see pmk_nb.openings)."""
    from pmk_nb.openings import plan_openings

    per_storey: dict[str, dict[str, int]] = {}
    shut = 0
    for st in building.storeys:
        plan = plan_openings(building, st.name)
        per_storey[st.name] = plan.rule_counts()
        shut += len(plan.shut_doors)
    rules: dict[str, int] = {}
    for counts in per_storey.values():
        for k, v in counts.items():
            rules[k] = rules.get(k, 0) + v
    return {
        "links_same_storey": sum(k.same_storey for k in building.links),
        "links_between_storeys": sum(not k.same_storey for k in building.links),
        "rules": rules,
        "rules_by_storey": per_storey,
        "doors_without_transition": shut,
        "unit_conflict": building.unit_conflict,
        "unit_suspect": None if building.unit_suspect is None else asdict(building.unit_suspect),
    }


def format_connectivity(c: dict[str, Any]) -> list[str]:
    words = {
        "door": "door geometry",
        "line": "transition line",
        "corridor": "corridor (whole boundary)",
        "middle": "middle of shared wall",
        "bridge": "passage across a gap",
        "apart": "cells apart (cannot open)",
    }
    rules = ", ".join(f"{n} by {words.get(k, k)}" for k, n in sorted(c["rules"].items())) or "none"
    lines = [
        f"  connectivity: {c['links_same_storey']} transitions within storeys, "
        f"{c['links_between_storeys']} between storeys (stairs, lifts)",
        f"    openings: {rules}",
    ]
    if c["doors_without_transition"]:
        lines.append(f"    {c['doors_without_transition']} door boundaries join cells with no transition: kept shut")
    if c["unit_suspect"]:
        lines.append(f"  UNIT SUSPECT: {c['unit_suspect']['message']}")
    if c["unit_conflict"]:
        lines.append(f"  UNIT WARNING: {c['unit_conflict']} (pmk convert --unit m|dm|cm|mm)")
    return lines


def run(args: argparse.Namespace) -> int:
    from pmk_nb.indoorgml import format_summary, read_building, summarize

    building = read_building(args.file, unit=args.unit, not_windows=args.not_windows, layers=args.layers, crs=args.crs)
    summary = summarize(building)
    summary["connectivity"] = connectivity(building)
    if args.json:
        json.dump(summary, sys.stdout, indent=2, ensure_ascii=False)
        sys.stdout.write("\n")
    else:
        print("\n".join([format_summary(summary), *format_connectivity(summary["connectivity"])]))
    return 0
