"""The options every `pmk` command shares: one name per concept, one default, one JSON shape.

Issue 29: the maps folder was ``--dir``, ``--maps-dir`` or ``--maps`` by command, the chair's size
``--chair-width`` beside ``--footprint-radius``, and ``convert`` required ``-r`` where the others
defaulted to 0.05. Each concept now has one visible spelling (:data:`CANONICAL`); the old spellings
still parse as hidden, deprecated aliases (:data:`ALIASES`), so scripts keep working.
``tests/cli/test_cli_options.py`` walks every parser against these tables.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn, TypeAlias

from pmk_nb.defaults import DEFAULT_RESOLUTION as DEFAULT_RESOLUTION  # declared once there, re-exported here
from pmk_nb.errors import PmkError

#: concept (the argparse dest) -> its one visible option name
CANONICAL: dict[str, str] = {
    "maps_dir": "--maps-dir",
    "chair_width": "--chair-width",
    "resolution": "--resolution",
    "json": "--json",
}

#: deprecated spelling -> the canonical option it stands for (parsed, never shown in --help)
ALIASES: dict[str, str] = {
    "--dir": "--maps-dir",  # pmk maps --dir (pmk demo's --dir is its own folder: --demo-dir)
    "--maps": "--maps-dir",  # pmk robot map-server / sim-node --maps
    "--footprint-radius": "--chair-width",  # pmk chair add: a radius, i.e. half the width
    "--flavour": "--ros",  # pmk sim: the message spelling
}

#: short forms allowed beside a canonical name
SHORT: dict[str, str] = {"resolution": "-r"}

#: what each command's ``add_parser`` receives: ``ArgumentParser.add_subparsers()``'s result (generic in the
#: stubs only)
if TYPE_CHECKING:
    Subparsers: TypeAlias = argparse._SubParsersAction[argparse.ArgumentParser]
else:
    Subparsers = argparse._SubParsersAction

MAPS_DIR_HELP = "maps folder (default: $PMK_MAPS_DIR or the user data folder)"


def add_maps_dir(
    p: argparse.ArgumentParser,
    *,
    aliases: tuple[str, ...] = (),
    default: Any = None,
    help: str = MAPS_DIR_HELP,
) -> None:
    """``--maps-dir DIR`` (dest ``maps_dir``), plus hidden deprecated ``aliases`` of the same dest."""
    p.add_argument("--maps-dir", type=Path, default=default, help=help)
    for alias in aliases:
        assert ALIASES.get(alias) == "--maps-dir", alias
        p.add_argument(alias, dest="maps_dir", type=Path, default=argparse.SUPPRESS, help=argparse.SUPPRESS)


def add_resolution(p: argparse.ArgumentParser, *, what: str = "metres per cell") -> None:
    """``--resolution/-r`` with the one default, :data:`DEFAULT_RESOLUTION`."""
    p.add_argument(
        "--resolution",
        "-r",
        type=float,
        default=DEFAULT_RESOLUTION,
        help=f"{what} (default {DEFAULT_RESOLUTION:g})",
    )


class UsageError(PmkError):
    """The command line itself is wrong (an unknown option, a missing argument): argparse's refusal as a type.

    Attributes:
        prog: the (sub-)command whose parser refused, e.g. ``pmk maps convert``.
        usage: that parser's usage line, as argparse prints it.
    """

    def __init__(self, message: str, *, prog: str, usage: str) -> None:
        super().__init__(message, hint=f"See `{prog} --help`.")
        self.prog = prog
        self.usage = usage


class JsonErrorParser(argparse.ArgumentParser):
    """A parser for a `--json` run: a refused command line raises :class:`UsageError`, which ``main`` prints as
    JSON on stdout (argparse would print usage on stderr and leave stdout empty); sub-parsers inherit it."""

    def error(self, message: str) -> NoReturn:
        raise UsageError(message, prog=self.prog, usage=self.format_usage().strip())


def wants_json(argv: list[str]) -> bool:
    """``--json`` among the arguments (before a ``--``): errors, the command line's own included, go out as JSON."""
    return "--json" in argv[: argv.index("--")] if "--" in argv else "--json" in argv


def add_json(p: argparse.ArgumentParser, what: str = "the result") -> None:
    """``--json``: the result as one JSON document on stdout; errors too (see :func:`error_json`)."""
    p.add_argument("--json", action="store_true", help=f"print {what} as JSON on stdout (errors too)")


def print_json(document: Any) -> None:
    """One JSON document on stdout (paths as strings), newline-terminated."""
    sys.stdout.write(json.dumps(document, indent=2, default=str) + "\n")
    sys.stdout.flush()


def _plain(value: Any) -> Any:
    """``value`` when JSON can carry it as is, else its text (paths, enums, nested errors)."""
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    return str(value)


def error_json(err: BaseException, command: str) -> dict[str, Any]:
    """An error as the JSON a script reads: ``{"ok": false, "command", "error": TYPE, "message", "hint",
    "fields": {attribute: value}}``; the fields are the error type's own (``path``, ``step``, ...)."""
    fields = {k: _plain(v) for k, v in vars(err).items() if not k.startswith("_") and k not in ("message", "hint")}
    return {
        "ok": False,
        "command": command,
        "error": type(err).__name__,
        "message": getattr(err, "message", str(err)),
        "hint": getattr(err, "hint", ""),
        "fields": fields,
    }


def add_layer_option(p: argparse.ArgumentParser) -> None:
    """--layer: draw the named space layer(s) instead of the navigable one the reader picks (one wording)."""
    p.add_argument(
        "--layer",
        action="append",
        default=[],
        dest="layers",
        metavar="NAME",
        help="draw this space layer (id or name) instead of the navigable one (repeatable; "
        "`pmk info` lists the layers not drawn and why)",
    )


def add_crs_option(p: argparse.ArgumentParser) -> None:
    """--crs: the frame of a plan's coordinates when the file is wrong or silent about it (one wording)."""
    p.add_argument(
        "--crs",
        default="auto",
        metavar="CRS",
        help="the coordinates' CRS: auto (default: the file's srsName, else judged), local (a local frame), "
        "or a CRS such as EPSG:3857 or EPSG:25832 (replaces the file's); large projected coordinates are "
        "read from a local origin, kept in the georeference",
    )


def add_not_window_option(p: argparse.ArgumentParser) -> None:
    """--not-window: the override `pmk check` offers when a cell it names as a window is a door (one wording)."""
    p.add_argument(
        "--not-window",
        action="append",
        default=[],
        dest="not_windows",
        metavar="CELL",
        help="a cell (name or id) taken for a window or sill that is really a door or floor: keep it "
        "navigable (repeatable; `pmk check` names the cells taken for windows)",
    )


def chair_width_arg(given: float | None) -> float:
    """--chair-width when given, else the width in the last used chair profile (Settings), else 0.70 m."""
    from pmk_nb.access import profile_chair_width
    from pmk_nb.chair import ProfileStore

    profile = None
    if given is None:
        try:
            profile = ProfileStore(secrets=False).last_used()
        except (PmkError, OSError, ValueError):  # an unreadable profile file: the default chair
            profile = None
    return profile_chair_width(given, profile)
