"""`pmk` command line: thin wrappers, one library call per command.

Each sub-command lives in the module that owns the feature and registers itself through
``add_parser(subparsers)`` / ``run(args) -> int``; this file only wires them up so that importing
``pmk_nb.cli`` stays cheap (features are imported when their command runs).
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

from pmk_nb.errors import PmkError

# command name -> module providing add_parser(subparsers) and run(args)
COMMANDS: dict[str, str] = {
    "info": "pmk_nb.commands.info",
    "convert": "pmk_nb.commands.convert",
    "maps": "pmk_nb.commands.maps",
    "sim": "pmk_nb.sim.cli",
    "send": "pmk_nb.chair.cli",
    "chair": "pmk_nb.chair.cli_profiles",
    "dashboard": "pmk_nb.ui.cli",
    "bench": "pmk_nb.commands.bench",
}


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="pmk", description="PMK Notebook: building plans to wheelchair maps.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for module_name in COMMANDS.values():
        try:
            module = importlib.import_module(module_name)
        except ModuleNotFoundError as err:
            if err.name and module_name.startswith(err.name):
                continue  # feature not installed in this build
            raise
        module.add_parser(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.run(args) or 0)
    except PmkError as err:
        print(f"pmk {args.command}: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"pmk {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
