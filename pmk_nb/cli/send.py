"""`pmk send NAME --chair PROFILE`: the Maps screen's Send button, for scripts."""

from __future__ import annotations

import argparse
import getpass
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from pmk_nb.cli.options import Subparsers, add_json, add_maps_dir, error_json, print_json
from pmk_nb.errors import DeployError, LibraryError, SettingsError
from pmk_nb.progress import Progress

if TYPE_CHECKING:
    from pmk_nb.chair import ChairProfile, ProfileStore
    from pmk_nb.rosmap import MapFiles


def add_parser(subparsers: Subparsers) -> None:
    p = subparsers.add_parser(
        "send",
        help="send a converted map to the chair and make it the live map",
        description="Upload NAME's map to the chair over SFTP, reload its map server, confirm the new map.",
    )
    p.add_argument("name", help="map name in the maps folder (or a path to a map YAML file)")
    p.add_argument("--chair", metavar="PROFILE", help="chair profile (default: the last used one)")
    p.add_argument("--storey", help="which storey's map, when the building has several")
    add_maps_dir(p)
    p.add_argument("--password-stdin", action="store_true", help="read the SSH password from standard input")
    p.add_argument("--timeout", type=float, default=15.0, help="network timeout per step in seconds (15)")
    p.add_argument("--reload-timeout", type=float, default=60.0, help="how long the map server may take (60)")
    p.add_argument("--confirm-timeout", type=float, default=10.0, help="how long to wait for the new map (10)")
    add_json(p, "the deploy report (map, chair, service, remote path, seconds)")
    p.set_defaults(run=run)


def pick_map(name: str, maps_dir: Path | None, storey: str | None) -> MapFiles:
    """The MapFiles to send: a generated map of NAME (one storey), or NAME as a YAML path."""
    from pmk_nb.library import MapsFolder
    from pmk_nb.rosmap import MapFiles

    as_path = Path(name).expanduser()
    if as_path.suffix.lower() in (".yaml", ".yml") and as_path.is_file():
        from pmk_nb.rosmap import read_map_yaml

        return MapFiles(yaml=as_path, image=Path(read_map_yaml(as_path).image), preview=None)
    folder = MapsFolder(maps_dir)
    if not folder.exists(name):
        orphans = [g for g in folder.orphans() if g.yaml.stem == name]
        if orphans:  # copied into the folder by hand, without an IndoorGML source (the original allowed it)
            return MapFiles(yaml=orphans[0].yaml, image=orphans[0].image, preview=orphans[0].preview)
        raise LibraryError(f"no map named {name!r} in {folder.root}; `pmk maps list` shows what is there")
    generated = folder.entry(name).generated
    if not generated:
        raise LibraryError(f"map {name!r} is not converted yet: run `pmk convert {name}` first")
    if storey is not None:
        generated = [g for g in generated if g.storey == storey]
        if not generated:
            have = ", ".join(str(g.storey) for g in folder.entry(name).generated)
            raise LibraryError(f"map {name!r} has no storey {storey!r} (storeys: {have})")
    elif len(generated) > 1:
        have = ", ".join(str(g.storey) for g in generated)
        raise LibraryError(f"map {name!r} has several storeys ({have}): choose one with --storey")
    chosen = generated[0]
    if chosen.broken:
        raise LibraryError(f"map {name!r}: {chosen.broken}; convert it again")
    return MapFiles(yaml=chosen.yaml, image=chosen.image, preview=chosen.preview)


def ask_password(profile: ChairProfile, store: ProfileStore, from_stdin: bool) -> str | None:
    """Password (or key passphrase) for this session: stdin, keyring/session, or prompt."""
    if from_stdin:
        line = sys.stdin.readline()
        if not line:
            raise SettingsError("--password-stdin given but standard input is empty")
        return line.rstrip("\r\n")
    saved = store.get_password(profile)
    if saved is not None or profile.auth == "key":
        return saved  # a key without passphrase needs none
    if not sys.stdin.isatty():
        raise SettingsError(
            f"chair {profile.name!r} needs the SSH password of {profile.ssh_user}: use --password-stdin"
        )
    return getpass.getpass(f"SSH password for {profile.ssh_user}@{profile.host}: ")


def upload_quarters() -> Callable[[Progress], bool]:
    """Whether to print a progress event: every event, except that the upload's many byte counts
    print once per quarter of the upload (and at its end)."""
    from pmk_nb.chair import STEP_SPANS

    lo, hi = STEP_SPANS["upload"]
    last_quarter = [-1]

    def wanted(p: Progress) -> bool:
        if p.step != "upload" or p.fraction is None:
            return True
        within = (p.fraction - lo) / (hi - lo)
        quarter = int(within * 4)
        if quarter == last_quarter[0] and within < 1.0:
            return False
        last_quarter[0] = quarter
        return True

    return wanted


def print_progress() -> Callable[[Progress], None]:
    """The terminal's progress lines: ``[step   ]  42.0%  message``."""
    wanted = upload_quarters()

    def show(p: Progress) -> None:
        if wanted(p):
            percent = f"{p.fraction * 100:5.1f}%" if p.fraction is not None else "     "
            print(f"[{p.step:7}] {percent}  {p.message}", flush=True)

    return show


def deploy_failure(err: DeployError) -> str:
    """The words the terminal uses for a failed send (the one place the CLI phrases deploy errors)."""
    step = f"{err.step}: " if err.step else ""
    after = ""
    if err.keeps_old_map is None and err.step in ("reload", "confirm"):
        after = " Whether the chair switched to the new map is unknown: look at its live map before sending again."
    return f"{step}{err}{after}"


def run(args: argparse.Namespace) -> int:
    from pmk_nb.chair import ProfileStore, close_links
    from pmk_nb.chair.deploy import deploy

    store = ProfileStore()
    if args.chair:
        profile = store.get(args.chair)
    else:
        last = store.last_used()
        if last is None:
            raise SettingsError("no chair profile yet: create one with `pmk chair add NAME --host ...`")
        profile = last
    files = pick_map(args.name, args.maps_dir, args.storey)
    password = ask_password(profile, store, args.password_stdin)
    if not args.json:
        print(f"sending {files.yaml.name} to {profile.name} ({profile.host})")
    try:
        report = deploy(
            files,
            profile,
            password=password,
            progress=(lambda p: None) if args.json else print_progress(),
            timeout=args.timeout,
            reload_timeout=args.reload_timeout,
            confirm_timeout=args.confirm_timeout,
        )
    except DeployError as err:
        if args.json:
            print_json(error_json(err, "send"))
        print(f"pmk send: error: {deploy_failure(err)}", file=sys.stderr)
        return 2
    finally:
        close_links()
    if password is not None and profile.auth == "password":
        store.set_password(profile, password)
    store.mark_used(profile.name)
    info = report.map_info
    if args.json:
        print_json(
            {
                "ok": True,
                "map": str(files.yaml),
                "chair": profile.name,
                "host": profile.host,
                "remote_yaml": str(report.remote_yaml),
                "service": report.service.name,
                "service_kind": report.service.kind,
                "elapsed_s": round(report.elapsed, 3),
                "width": info.width,
                "height": info.height,
                "resolution": info.resolution,
                "notes": list(report.notes),
            }
        )
        return 0
    for note in report.notes:
        print(f"note: {note}")
    print(
        f"done in {report.elapsed:.1f} s: {report.remote_yaml} loaded by {report.service.name} "
        f"({report.service.kind}); chair publishes {info.width}x{info.height} at {info.resolution:g} m"
    )
    return 0
