"""`pmk maps list|import|download|convert|delete`: the MAPS screen of the original app, scriptable.

publish|catalogue|get (map catalogues, issue 27) live in ``maps_catalogue``.

Each sub-command is one :class:`~pmk_nb.library.folder.MapsFolder` call; errors are LibraryError (a
PmkError), which ``pmk_nb.cli`` prints and turns into exit status 2.
"""

from __future__ import annotations

import argparse
import contextlib
import sys
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING

from pmk_nb.cli import maps_catalogue
from pmk_nb.cli.convert import add_raster_options
from pmk_nb.cli.options import Subparsers, add_json, add_maps_dir, add_resolution, chair_width_arg, print_json
from pmk_nb.progress import Progress

if TYPE_CHECKING:
    from pmk_nb.library import GeneratedMap, MapEntry, MapsFolder


def add_parser(subparsers: Subparsers) -> None:
    p = subparsers.add_parser(
        "maps",
        help="list, import, download, convert and delete maps in the maps folder",
        description="Manage the maps folder (ALMA_MAPS): IndoorGML sources and the maps generated from them.",
    )
    add_maps_dir(p, aliases=("--dir",))
    # --maps-dir is accepted after the action too (`pmk maps list --maps-dir D`); SUPPRESS keeps the outer value
    common = argparse.ArgumentParser(add_help=False)
    add_maps_dir(common, aliases=("--dir",), default=argparse.SUPPRESS)
    add_json(common)  # every action: its result, or its error, as one JSON document
    sub = p.add_subparsers(dest="maps_command", metavar="ACTION", required=True)

    sub.add_parser("list", parents=[common], help="list the IndoorGML maps and their generated files")

    imp = sub.add_parser("import", parents=[common], help="copy an IndoorGML file into the maps folder")
    imp.add_argument("path", help="IndoorGML file (.gml / .xml)")
    imp.add_argument("--name", help="map name (default: the file name without extension)")
    imp.add_argument("--overwrite", action="store_true", help="replace a map with the same name")

    dl = sub.add_parser("download", parents=[common], help="download an IndoorGML map from an http(s) URL")
    dl.add_argument("url", help="http(s) address of the IndoorGML file")
    dl.add_argument("name", help="name to save the map under")
    dl.add_argument("--overwrite", action="store_true", help="replace a map with the same name")
    dl.add_argument("--timeout", type=float, default=30.0, help="seconds without data before giving up")
    dl.add_argument("--deadline", type=float, default=120.0, help="seconds the whole download may take")
    dl.add_argument("--max-mb", type=float, default=50.0, help="refuse files larger than this (MiB)")
    dl.add_argument(
        "--allow-local",
        action="store_true",
        help="also download from loopback and LAN addresses (a lab server); refused by default",
    )

    cv = sub.add_parser(
        "convert", parents=[common], help="generate map_server files (YAML + image + preview) from a map"
    )
    cv.add_argument("name", help="building in the maps folder (see pmk maps list)")
    add_resolution(cv)
    cv.add_argument("--storey", action="append", dest="storeys", help="convert only this storey (repeatable)")
    add_raster_options(cv)

    rm = sub.add_parser("delete", parents=[common], help="delete a map and every file generated from it")
    rm.add_argument("name", help="building to delete from the maps folder")
    maps_catalogue.add_parsers(sub, common)  # publish, catalogue, get (issue 27)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from pmk_nb.errors import AlreadyExists, GridTooLarge, LibraryError, PmkError

    try:
        return _run(args)
    except AlreadyExists as err:  # the CLI's words: the option, not the keyword argument
        raise PmkError(f"map {err.name!r} already exists.", hint="Pass --overwrite to replace it.") from err
    except LibraryError as err:
        cause = err.__cause__
        if isinstance(cause, GridTooLarge):
            raise PmkError(err.message, hint=f"Use --resolution {cause.suggested_resolution:g} or coarser.") from err
        raise


def _run(args: argparse.Namespace) -> int:
    from pmk_nb.library import MapsFolder

    folder = MapsFolder(args.maps_dir, allow_local=getattr(args, "allow_local", None) or None)
    action = args.maps_command
    if action not in FOLDER_MAY_BE_NEW:
        folder.require_root()  # a mistyped --maps-dir is an error, never an empty folder
    if action == "list":
        return _list(folder, as_json=args.json)
    if action == "import":
        entry = folder.import_file(args.path, args.name, overwrite=args.overwrite)
        return _done(args, f"imported {args.path} as map {entry.name!r} ({entry.source})", _entry_json(entry))
    if action == "download":
        return _download(folder, args)
    if action == "convert":
        return _convert(folder, args)
    if action in maps_catalogue.ACTIONS:
        return maps_catalogue.run(action, folder, args)
    if action == "delete":
        entry = folder.entry(args.name)
        folder.delete(entry.name)
        said = f"deleted map {entry.name!r}: {entry.source.name} and {len(entry.generated)} generated map(s)"
        return _done(args, said, _entry_json(entry))
    raise AssertionError(action)  # argparse restricts the choices


#: actions that create the maps folder or do not read it; the others refuse a folder that does not exist
FOLDER_MAY_BE_NEW = ("import", "download", "get", "catalogue")


def _done(args: argparse.Namespace, said: str, doc: dict[str, object]) -> int:
    """The one line an action prints, or with ``--json`` its result ``{"ok": true, "action", ...}``."""
    if args.json:
        print_json({"ok": True, "action": args.maps_command, **doc})
    else:
        print(said)
    return 0


def _entry_json(e: MapEntry) -> dict[str, object]:
    """One building of the maps folder as `pmk maps list --json` shows it."""
    return {
        "name": e.name,
        "source": str(e.source),
        "size": e.size,
        "status": e.status,
        "generated": [_map_json(g) for g in e.generated],
    }


def _describe(gm: GeneratedMap) -> str:
    storey = f"storey {gm.storey}: " if gm.storey is not None else ""
    if gm.broken:
        return f"{storey}{gm.yaml.name} BROKEN ({gm.broken})"
    stale = " STALE (source changed since; convert again)" if gm.stale else ""
    return f"{storey}{gm.yaml.name} {gm.width}x{gm.height} cells at {gm.resolution:g} m{stale}"


def _map_json(gm: GeneratedMap) -> dict[str, object]:
    """One generated map for `pmk maps list --json` (keys documented in the README)."""
    return {
        "storey": gm.storey,
        "yaml": str(gm.yaml),
        "image": str(gm.image),
        "resolution": gm.resolution,
        "width": gm.width,
        "height": gm.height,
        "stale": gm.stale,
        "broken": gm.broken or None,
    }


def _list(folder: MapsFolder, *, as_json: bool = False) -> int:
    entries: list[MapEntry] = folder.list()
    if as_json:
        print_json(
            {
                "maps_dir": str(folder.root),
                "maps": [_entry_json(e) for e in entries],
                "orphans": [_map_json(g) for g in folder.orphans()],
            }
        )
        return 0
    print(f"maps folder: {folder.root}")
    if not entries:
        print("no maps yet: use `pmk maps import FILE` or `pmk maps download URL NAME`")
    for e in entries:
        print(f"{e.name}  ({e.source.name}, {e.size} bytes)  {e.status}")
        for gm in e.generated:
            print(f"    {_describe(gm)}")
    orphans = folder.orphans()
    if orphans:
        print("maps without an IndoorGML source:")
        for gm in orphans:
            print(f"    {_describe(gm)}")
    return 0


@contextlib.contextmanager
def _status_line() -> Iterator[Callable[[str], None]]:
    """``show(text)`` rewrites one progress line on stderr when it is a terminal (a log gets none)."""
    interactive = sys.stderr.isatty()  # never on stdout: with --json that is the one JSON document

    def show(text: str) -> None:
        if interactive:
            print(f"\r{text}", end="", file=sys.stderr, flush=True)

    try:
        yield show
    finally:
        if interactive:
            print(file=sys.stderr)


def _download(folder: MapsFolder, args: argparse.Namespace) -> int:
    with _status_line() as show:

        def progress(p: Progress) -> None:
            show(f"downloading: {p.message}")

        entry = folder.download(
            args.url,
            args.name,
            overwrite=args.overwrite,
            timeout=args.timeout,
            deadline=args.deadline,
            max_bytes=int(args.max_mb * 1024 * 1024),
            progress=progress,
        )
    said = f"downloaded {args.url} as map {entry.name!r} ({entry.size} bytes, {entry.source})"
    return _done(args, said, _entry_json(entry))


def accessibility_line(yaml_path: Path) -> str:
    """The accessibility summary kept in a map's rooms file ('' when it has none)."""
    from pmk_nb.access import sidecar_doc

    report = (sidecar_doc(yaml_path) or {}).get("accessibility") or {}
    c = report.get("counts")
    if not c:
        return ""
    if report.get("graph_lost") or report.get("checked") is False:  # never "0/0 passable": nothing was checked
        return f"NOTHING CHECKED: {report.get('graph_lost') or 'no transition of the navigation graph on this storey'}"
    return (
        f"{c['passable_chair']}/{c['links']} transitions passable for a {report['chair_width']:.2f} m chair, "
        f"{c['narrow']} narrow, {c['unreachable']} unreachable, {c['leaks']} leaks"
    )


def _convert(folder: MapsFolder, args: argparse.Namespace) -> int:
    from pmk_nb.library import ConvertOptions

    with _status_line() as show:

        def progress(p: Progress) -> None:
            show(f"{(p.fraction or 0.0) * 100:5.1f}% {f'{p.step} {p.message}':<50}")

        options = ConvertOptions(
            resolution=args.resolution,
            storeys=args.storeys,
            wall_thickness=args.wall_thickness,
            max_wall_gap=args.max_wall_gap,
            unit=args.unit,
            crs=args.crs,
            image_format=args.image_format,
            door_width=args.door_width,
            chair_width=chair_width_arg(args.chair_width),
            not_windows=tuple(args.not_windows),
            layers=tuple(args.layers),
        )
        maps = folder.convert_with(args.name, options, progress=progress)
    if args.json:
        converted = [{**_map_json(gm), "accessibility": accessibility_line(gm.yaml) or None} for gm in maps]
        print_json({"ok": True, "action": "convert", "name": args.name, "maps": converted})
        return 0
    print(f"converted map {args.name!r} at {args.resolution:g} m per cell:")
    for gm in maps:
        files = ", ".join(p.name for p in (gm.yaml, gm.image, gm.preview) if p is not None)
        print(f"    {_describe(gm)}  [{files}]")
        access = accessibility_line(gm.yaml)
        if access:
            print(f"        accessibility: {access}")
    return 0
