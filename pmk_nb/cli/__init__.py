"""`pmk` command line: thin wrappers, one library call per command.

Each sub-command lives in the module that owns the feature and provides ``add_parser(subparsers)``
(which sets ``run``) and ``run(args) -> int``. Only the module of the command being run is imported,
so `pmk info` does not pay for the simulator's or the dashboard's imports.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from collections.abc import Sequence

from pmk_nb.errors import PmkError

# command name -> (module providing add_parser/run, one-line help)
COMMANDS: dict[str, tuple[str, str]] = {
    "info": ("pmk_nb.cli.info", "describe an IndoorGML file: storeys, cells, doors, units"),
    "convert": ("pmk_nb.cli.convert", "IndoorGML file -> ROS map_server YAML + image per storey"),
    "check": ("pmk_nb.cli.check", "wheelchair accessibility of a building plan or a written map (exit 1: problems)"),
    "maps": ("pmk_nb.cli.maps", "the maps folder: list, import, download, convert, delete; publish, catalogue, get"),
    "sim": ("pmk_nb.cli.sim", "run the simulated chair (rosbridge + SFTP)"),
    "send": ("pmk_nb.cli.send", "send a map to a chair and reload it there"),
    "chair": ("pmk_nb.cli.chair", "manage chair profiles; test a connection"),
    "dashboard": ("pmk_nb.cli.dashboard", "serve the dashboard with Voilà"),
    "demo": ("pmk_nb.cli.demo", "simulated chair + dashboard with the sample map"),
    "hub": ("pmk_nb.cli.hub", "JupyterHub for a class: a dashboard and a simulated chair per student"),
    "bench": ("pmk_nb.cli.bench", "run the benchmarks, write bench/results.md"),
    "robot": ("pmk_nb.cli.robot", "chair-side ROS 2 nodes: the PMK map server, the simulated chair"),
}
BROKEN_PIPE = 128 + 13  # the exit status of a process ended by SIGPIPE


def build_parser(command: str | None = None, *, json_errors: bool = False) -> argparse.ArgumentParser:
    """The full parser for ``command``; without one, a parser that only lists the commands.

    ``json_errors``: a refused command line raises ``UsageError`` instead of exiting (``main`` with ``--json``).
    """
    from pmk_nb.cli.options import JsonErrorParser

    parser_class = JsonErrorParser if json_errors else argparse.ArgumentParser
    parser = parser_class(prog="pmk", description="PMK Notebook: building plans to wheelchair maps.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, (module_name, help_text) in COMMANDS.items():
        if name == command:
            importlib.import_module(module_name).add_parser(sub)
        else:
            sub.add_parser(name, help=help_text, add_help=False)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    command = next((a for a in argv if not a.startswith("-")), None)
    from pmk_nb.cli.options import UsageError, error_json, print_json, wants_json

    as_json = wants_json(argv)
    parser = build_parser(command if command in COMMANDS else None, json_errors=as_json)
    try:
        args = parser.parse_args(argv)
    except UsageError as err:  # only with --json: the refusal on stdout as JSON, argparse's words on stderr
        print_json(error_json(err, command if command in COMMANDS else "pmk"))
        print(f"{err.usage}\n{err.prog}: error: {err.message}", file=sys.stderr)
        return err.exit_code
    try:
        return int(args.run(args) or 0)
    except PmkError as err:
        if getattr(args, "json", False):  # a script reads stdout: the error as JSON there too
            print_json(error_json(err, args.command))
        print(f"pmk {args.command}: error: {err}", file=sys.stderr)
        return err.exit_code  # 2, or what the error's type says (pmk sim: a port taken)
    except KeyboardInterrupt:
        print(f"pmk {args.command}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # the reader left (`pmk check --json FILE | head`): end quietly, as a shell tool killed by SIGPIPE
        # would; stdout goes to /dev/null so the interpreter's final flush cannot fail again
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return BROKEN_PIPE


if __name__ == "__main__":
    sys.exit(main())
