"""`pmk maps publish|catalogue|get`: share maps between chairs and tablets as a static STAC catalogue.

publish writes the folder a web server serves; catalogue lists what one offers (and what is new or
changed since it was installed here); get installs a building, every file checked. Refusals are
typed errors (:mod:`pmk_nb.errors`): ``pmk_nb.cli`` prints them and exits with status 2.
"""

from __future__ import annotations

import argparse
from dataclasses import asdict
from typing import TYPE_CHECKING

from pmk_nb.cli.options import Subparsers, error_json, print_json

if TYPE_CHECKING:
    from pmk_nb.catalogue import Catalogue
    from pmk_nb.library import MapsFolder

ACTIONS = ("publish", "catalogue", "get")


def add_parsers(sub: Subparsers, common: argparse.ArgumentParser) -> None:
    pub = sub.add_parser("publish", parents=[common], help="publish converted maps as a static STAC catalogue")
    pub.add_argument("names", nargs="*", metavar="NAME", help="maps to publish (default: every converted map)")
    pub.add_argument("--out", required=True, metavar="SITE", help="folder to write (serve it with any web server)")
    pub.add_argument("--title", help="the catalogue's title (default: kept, else 'PMK maps')")

    net = argparse.ArgumentParser(add_help=False)
    net.add_argument("--allow-local", action="store_true", help="also reach loopback and LAN addresses (a lab server)")
    net.add_argument(
        "--allow-host",
        action="append",
        default=[],
        metavar="HOST",
        help="assets may also come from this host (repeatable)",
    )
    cat = sub.add_parser("catalogue", parents=[common, net], help="list the buildings and storeys of a catalogue")
    cat.add_argument("url", help="http(s) address of catalog.json (or of its folder)")

    get = sub.add_parser("get", parents=[common, net], help="install a building from a catalogue, every file checked")
    get.add_argument("url", help="http(s) address of catalog.json (or of its folder)")
    get.add_argument("name", help="building (collection id) to install")
    get.add_argument("--storey", action="append", dest="storeys", default=[], help="only this storey (repeatable)")
    get.add_argument("--overwrite", action="store_true", help="replace a map of that name made elsewhere")
    get.add_argument("--max-mb", type=float, default=200.0, help="refuse a file larger than this (MiB)")


def run(action: str, folder: MapsFolder, args: argparse.Namespace) -> int:
    if action == "publish":
        return _publish(folder, args)
    from pmk_nb.catalogue import read_catalogue

    catalogue = read_catalogue(args.url, allow_local=args.allow_local, allow_hosts=args.allow_host)
    if action == "catalogue":
        return _list(folder, catalogue, as_json=args.json)
    return _get(folder, catalogue, args)


def _publish(folder: MapsFolder, args: argparse.Namespace) -> int:
    from pmk_nb.catalogue.publish import publish

    result = publish(folder, args.out, args.names, title=args.title)
    if args.json:
        print_json({"ok": True, "action": "publish", **asdict(result)})
        return 0
    counts = f"{len(result.written)} file(s) written, {result.unchanged} unchanged, {len(result.removed)} removed"
    print(f"published {', '.join(result.buildings)} to {result.site / 'catalog.json'}: {counts}")
    for path in result.written:
        print(f"    wrote {path.relative_to(result.site)}")
    return 0


def _size(n: int) -> str:
    return f"{n / 1048576:.1f} MiB" if n >= 1048576 else f"{n / 1024:.1f} KiB"


def _list(folder: MapsFolder, catalogue: Catalogue, *, as_json: bool) -> int:
    from pmk_nb.catalogue import InstallRecord

    record = InstallRecord(folder.root)
    status = {b.id: record.status(b, catalogue.url, present=folder.exists(b.id)) for b in catalogue.buildings}
    if as_json:
        doc = {
            "url": catalogue.url,
            "title": catalogue.title,
            "buildings": [
                {**asdict(b), "size": b.size, "updated": b.updated, "status": status[b.id]} for b in catalogue.buildings
            ],
            "refused": [{**error_json(r.error, "maps"), "id": r.id, "url": r.url} for r in catalogue.refused],
        }
        print_json(doc)
        return 0
    print(f"catalogue {catalogue.title!r}: {catalogue.url}")
    if not catalogue.buildings:
        print("no buildings")
    for b in catalogue.buildings:
        print(f"{b.id}  {len(b.storeys)} storey(s), {_size(b.size)}, updated {b.updated}  [{status[b.id]}]")
        for s in b.storeys:
            where = f"storey {s.storey}: " if s.storey else ""
            print(f"    {where}{s.id} {s.width}x{s.height} cells at {s.resolution:g} m, {_size(s.size)}, {s.updated}")
    for r in catalogue.refused:  # listed apart: nothing of it can be installed
        print(f"{r.id}  REFUSED: {r.error}")
    return 0


def _get(folder: MapsFolder, catalogue: Catalogue, args: argparse.Namespace) -> int:
    from pmk_nb.catalogue.install import install

    result = install(
        catalogue,
        args.name,
        folder,
        storeys=args.storeys,
        overwrite=args.overwrite,
        max_bytes=int(args.max_mb * 1024 * 1024),
        allow_hosts=args.allow_host,
    )
    if args.json:
        print_json({"ok": True, "action": "get", **asdict(result)})
        return 0
    print(
        f"installed {result.name!r} ({', '.join(result.storeys)}): {len(result.files)} files, "
        f"{result.bytes} bytes, every size and SHA-256 checked"
    )
    return 0
