"""`pmk send NAME --chair PROFILE`: the Maps screen's Send button, for scripts."""

from __future__ import annotations

import argparse
import getpass
import sys
from pathlib import Path
from typing import Any

from pmk_nb.errors import DeployError, LibraryError, PmkError, SettingsError


def add_parser(subparsers: Any) -> None:
    p = subparsers.add_parser(
        "send",
        help="send a converted map to the chair and make it the live map",
        description="Upload NAME's map to the chair over SFTP, reload its map server, confirm the new map.",
    )
    p.add_argument("name", help="map name in the maps folder (or a path to a map YAML file)")
    p.add_argument("--chair", metavar="PROFILE", help="chair profile (default: the last used one)")
    p.add_argument("--storey", help="which storey's map, when the building has several")
    p.add_argument("--maps-dir", type=Path, help="maps folder (default: $PMK_MAPS_DIR or the user data dir)")
    p.add_argument("--password-stdin", action="store_true", help="read the SSH password from standard input")
    p.add_argument("--timeout", type=float, default=15.0, help="network timeout per step in seconds (15)")
    p.add_argument("--reload-timeout", type=float, default=60.0, help="how long the map server may take (60)")
    p.add_argument("--confirm-timeout", type=float, default=10.0, help="how long to wait for the new map (10)")
    p.set_defaults(run=run)


def pick_map(name: str, maps_dir: Path | None, storey: str | None) -> Any:
    """The MapFiles to send: a generated map of NAME (one storey), or NAME as a YAML path."""
    from pmk_nb.library.folder import MapsFolder
    from pmk_nb.rosmap.files import MapFiles

    as_path = Path(name).expanduser()
    if as_path.suffix.lower() in (".yaml", ".yml") and as_path.is_file():
        from pmk_nb.rosmap.files import read_map_yaml

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


def ask_password(profile: Any, store: Any, from_stdin: bool) -> str | None:
    """Password (or key passphrase) for this session: stdin, keyring/session, or prompt."""
    if from_stdin:
        line = sys.stdin.readline()
        if not line:
            raise SettingsError("--password-stdin given but standard input is empty")
        return line.rstrip("\r\n")
    saved = store.get_password(profile.name)
    if saved is not None or profile.auth == "key":
        return saved  # a key without passphrase needs none
    if not sys.stdin.isatty():
        raise SettingsError(
            f"chair {profile.name!r} needs the SSH password of {profile.ssh_user}: use --password-stdin"
        )
    return getpass.getpass(f"SSH password for {profile.ssh_user}@{profile.host}: ")


def run(args: argparse.Namespace) -> int:
    from pmk_nb.chair.deploy import STEP_SPANS, close_links, deploy
    from pmk_nb.chair.profiles import ProfileStore

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
    print(f"sending {files.yaml.name} to {profile.name} ({profile.host})")
    last_bucket = [-1]

    def progress(step: str, fraction: float, message: str) -> None:
        if step == "upload" and message.endswith("KiB"):  # byte counts: one line per quarter of the upload
            bucket = int(fraction / STEP_SPANS["upload"][1] * 4)
            if bucket == last_bucket[0]:
                return
            last_bucket[0] = bucket
        print(f"[{step:7}] {fraction * 100:5.1f}%  {message}", flush=True)

    try:
        report = deploy(
            files,
            profile,
            password=password,
            progress=progress,
            timeout=args.timeout,
            reload_timeout=args.reload_timeout,
            confirm_timeout=args.confirm_timeout,
        )
    except DeployError:
        raise
    except PmkError as err:
        raise DeployError(str(err)) from err
    finally:
        close_links()
    if password is not None and profile.auth == "password":
        store.set_password(profile.name, password)
    store.mark_used(profile.name)
    for note in report.notes:
        print(f"note: {note}")
    info = report.map_info
    print(
        f"done in {report.elapsed:.1f} s: {report.remote_yaml} loaded by {report.service.name} "
        f"({report.service.flavour}); chair publishes {info.width}x{info.height} at {info.resolution:g} m"
    )
    return 0
