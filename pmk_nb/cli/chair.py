"""`pmk chair list|add|show|delete|test`: the Settings screen's form, for scripts and kiosks."""

from __future__ import annotations

import argparse
import dataclasses
import json
from typing import TYPE_CHECKING, TypedDict

from pmk_nb.cli.options import Subparsers, add_json, print_json
from pmk_nb.errors import PmkError, SettingsError

if TYPE_CHECKING:
    from pmk_nb.chair import ChairProfile, ProfileStore

# option -> (ChairProfile field, type, help); everything but name, which is positional
_FIELDS: list[tuple[str, type, str]] = [
    ("host", str, "chair IP address or host name"),
    ("port", int, "rosbridge port (9090)"),
    ("odom-topic", str, "odometry topic (/odom)"),
    ("scan-topic", str, "laser scan topic (/scan)"),
    ("pose-source", str, "odometry | pose_topic | tf"),
    ("pose-topic", str, "pose topic when pose-source is pose_topic (/amcl_pose)"),
    ("ssh-user", str, "login name on the chair"),
    ("ssh-port", int, "SSH port (22)"),
    ("auth", str, "password | key"),
    ("key-file", str, "private key file when auth is key"),
    ("remote-maps-dir", str, "maps folder on the chair (~/ALMA_MAPS)"),
    ("reload-service", str, "auto or a service name like /change_map"),
    ("reload-kind", str, "auto | ros1 | nav2 | mapupdate"),
    ("known-hosts", str, "known_hosts file for the chair's SSH key"),
    ("host-key-check", str, "tofu (trust on first use) | strict"),
    ("tls-ca-file", str, "with --tls: CA file that signs the chair's certificate (default: pin it on first use)"),
]


def add_parser(subparsers: Subparsers) -> None:
    p = subparsers.add_parser("chair", help="manage chair profiles (connection settings)")
    sub = p.add_subparsers(dest="action", metavar="ACTION")  # bare `pmk chair` lists
    listing = sub.add_parser("list", help="list profiles (* = default)")
    add_json(listing, "the profiles and which is the default")
    listing.set_defaults(run=run_list)
    add = sub.add_parser("add", help="create or update a profile (it becomes the default)")
    add.add_argument("name", help="name of the new profile")
    for option, kind, text in _FIELDS:
        add.add_argument(f"--{option}", type=kind, help=text)
    add.add_argument(
        "--chair-width",
        type=float,
        metavar="W",
        help="the wheelchair's width in metres (0.70): map checks, and the live view's circle (radius W/2)",
    )
    # deprecated: the same concept as a radius (half the width); kept so old scripts still work
    add.add_argument("--footprint-radius", type=float, default=None, help=argparse.SUPPRESS)
    add.add_argument(
        "--tls", action=argparse.BooleanOptionalAction, default=None, help="rosbridge over TLS (wss://) or not"
    )
    add.add_argument("--password-stdin", action="store_true", help="remember a password read from stdin")
    add.add_argument(
        "--key",
        choices=("auto",),
        default=None,
        help="auto: make an ed25519 key in the settings folder (if none), install it on the chair with one "
        "password login (the password is not kept), then log in with the key: no password asked again",
    )
    add.set_defaults(run=run_add)
    show = sub.add_parser("show", help="print a profile as JSON")
    show.add_argument("name", nargs="?", help="profile (default: the last used one)")
    add_json(show, "the profile (always JSON; accepted for symmetry)")
    show.set_defaults(run=run_show)
    delete = sub.add_parser("delete", help="delete a profile (and its remembered password)")
    delete.add_argument("name", help="profile to delete")
    delete.set_defaults(run=run_delete)
    test = sub.add_parser("test", help="test rosbridge and SSH access of a profile")
    test.add_argument("name", nargs="?", help="profile (default: the last used one)")
    test.add_argument("--password-stdin", action="store_true", help="read the SSH password from stdin")
    test.add_argument("--timeout", type=float, default=5.0, help="seconds to wait for the chair (default 5)")
    test.add_argument("--no-ssh", action="store_true", help="only test rosbridge")
    add_json(test, "each part's result (rosbridge, ssh: ok, detail, error type)")
    test.add_argument(
        "--trust-fingerprint",
        metavar="SHA256",
        help="wss: pin the chair's certificate without a question when it has this SHA-256 fingerprint "
        "(openssl x509 -noout -fingerprint -sha256 on the chair); for scripts and kiosks without a terminal",
    )
    test.set_defaults(run=run_test)
    p.set_defaults(run=run_list, json=False)


def _store() -> ProfileStore:
    from pmk_nb.chair import ProfileStore

    return ProfileStore()


def _profile(store: ProfileStore, name: str | None) -> ChairProfile:
    if name:
        return store.get(name)
    last = store.last_used()
    if last is None:
        raise SettingsError("no chair profile yet: create one with `pmk chair add NAME --host ...`")
    return last


def run_list(args: argparse.Namespace) -> int:
    store = _store()
    last = store.last_used()
    profiles = store.list()
    if args.json:
        print_json(
            {
                "profiles_file": str(store.path),
                "default": None if last is None else last.name,
                "profiles": [pr.to_dict() for pr in profiles],
            }
        )
        return 0
    if not profiles:
        print(f"no chair profiles in {store.path}")
    for profile in profiles:
        mark = "*" if last is not None and profile.name == last.name else " "
        who = f"{profile.ssh_user}@" if profile.ssh_user else ""
        ssh = f"{who}{profile.host}:{profile.ssh_port}"
        print(f"{mark} {profile.name:20} {profile.bridge_url}  ssh {ssh}")
    return 0


def run_add(args: argparse.Namespace) -> int:
    from pmk_nb.chair import ChairProfile

    store = _store()
    changes = {
        option.replace("-", "_"): getattr(args, option.replace("-", "_"))
        for option, _kind, _text in _FIELDS
        if getattr(args, option.replace("-", "_")) is not None
    }
    if args.tls is not None:
        changes["tls"] = args.tls
    width = args.chair_width if args.chair_width is not None else None
    if width is None and args.footprint_radius is not None:
        width = 2 * args.footprint_radius
    if width is not None:  # one concept: the width for checks, half of it for the circle drawn
        changes["chair_width"], changes["footprint_radius"] = width, width / 2
    try:
        current = store.get(args.name)
    except SettingsError:
        if "host" not in changes:
            raise SettingsError(f"new profile {args.name!r} needs --host") from None
        current = ChairProfile(name=args.name, host=changes["host"])
    profile = dataclasses.replace(current, **changes)
    if args.key == "auto":
        return _add_with_key(store, profile, args)
    store.save(profile)
    if args.password_stdin:
        import sys

        store.set_password(profile, sys.stdin.readline().rstrip("\r\n"))
        print(f"password kept in {store.password_storage}")
    print(f"saved chair profile {profile.name!r} in {store.path} (now the default)")
    if store.backup_of_corrupt is not None:
        print(f"note: the unreadable profiles file was kept as {store.backup_of_corrupt}")
    return 0


def _add_with_key(store: ProfileStore, profile: ChairProfile, args: argparse.Namespace) -> int:
    """`pmk chair add --key auto`: one password login installs the key; the profile keeps the key only."""
    import getpass
    import sys

    from pmk_nb.chair import setup_key

    profile.validate()
    if args.password_stdin:
        password = sys.stdin.readline().rstrip("\r\n")
    else:
        password = getpass.getpass(f"password of {profile.ssh_user}@{profile.host} (once, to install the key): ")
    keyed, added = setup_key(profile, password)
    store.save(keyed)
    state = "installed on the chair" if added else "already on the chair"
    print(f"key {keyed.key_file} {state}; a key-only login works")
    print(f"saved chair profile {keyed.name!r} in {store.path} (auth key, now the default)")
    return 0


def run_show(args: argparse.Namespace) -> int:
    profile = _profile(_store(), args.name)
    print(json.dumps(profile.to_dict(), indent=2))
    return 0


def run_delete(args: argparse.Namespace) -> int:
    store = _store()
    store.delete(args.name)
    print(f"deleted chair profile {args.name!r}")
    return 0


def certificate_trusted(err: BaseException | None, expected: str | None) -> bool:
    """First contact with a wss chair: pin its certificate when a person says so (a terminal) or it
    has the ``--trust-fingerprint`` given; without a terminal nothing is trusted (False: refused)."""
    import sys

    from pmk_nb.chair.link import trust_certificate
    from pmk_nb.errors import UnknownChairCertificate
    from pmk_nb.tlscert import parse_fingerprint

    if not isinstance(err, UnknownChairCertificate):
        return False
    if expected is not None:
        wanted = parse_fingerprint(expected)
        if wanted is None:
            raise SettingsError(f"--trust-fingerprint {expected!r}: give a SHA-256 fingerprint (64 hex digits)")
        if wanted != err.presented:
            print(f"the chair's certificate is SHA-256 {err.presented}, not the {wanted} given: refused")
            return False
    elif sys.stdin.isatty():
        print(f"First TLS connection to {err.host}:{err.port}. The chair's certificate has the SHA-256 fingerprint")
        print(f"  {err.presented}")
        print("Compare it with the chair's: openssl x509 -noout -fingerprint -sha256 -in CERTFILE")
        if input("Trust this certificate? [y/N] ").strip().lower() not in ("y", "yes"):
            return False
    else:  # no terminal, no fingerprint given: never trust silently (the report says what to do)
        return False
    trust_certificate(err)
    print(f"pinned in {err.known_certs}")
    return True


class PartResult(TypedDict):
    """One part of `pmk chair test` (rosbridge or ssh), as printed and as ``--json`` lists it."""

    part: str
    target: str
    ok: bool
    detail: str
    error: str | None  # the error's type name when not ok


def _part(name: str, target: str, ok: bool, detail: str, err: BaseException | None = None) -> PartResult:
    """One line of `pmk chair test`: what was tested, whether it worked, and the error's type when not."""
    return {
        "part": name,
        "target": target,
        "ok": ok,
        "detail": detail,
        "error": None if err is None else type(err).__name__,
    }


def _test_bridge(profile: ChairProfile, args: argparse.Namespace) -> tuple[PartResult, list[str]]:
    from pmk_nb.chair import close_links, link_for

    url = profile.bridge_url
    try:
        link = link_for(profile)
        report = link.test_connection(timeout=args.timeout)
        if not report.ok and certificate_trusted(report.error, args.trust_fingerprint):
            report = link.test_connection(timeout=args.timeout)
        if report.ok:
            info = report.map_info
            about = f"map {info.width}x{info.height} at {info.resolution:g} m" if info else "no map published"
            return _part("rosbridge", url, True, f"{about}, {report.elapsed:.2f} s"), list(report.notes)
        return _part("rosbridge", url, False, str(report.reason), report.error), []
    except PmkError as err:
        return _part("rosbridge", url, False, str(err), err), []
    finally:
        close_links()


def _test_ssh(profile: ChairProfile, store: ProfileStore, args: argparse.Namespace) -> PartResult:
    from pmk_nb.chair import check_ssh
    from pmk_nb.cli.send import ask_password

    target = f"{profile.ssh_user}@{profile.host}:{profile.ssh_port}"
    try:
        password = ask_password(profile, store, args.password_stdin)
        check = check_ssh(profile, password=password, timeout=args.timeout)
        state = "exists" if check.exists else "will be created on first send"
        trusted = " (newly trusted)" if check.host_key.newly_trusted else ""
        if password is not None and profile.auth == "password":
            store.set_password(profile, password)
        detail = f"host key {check.host_key.fingerprint}{trusted}; {check.remote_dir} {state}"
        return _part("ssh", target, True, detail)
    except PmkError as err:
        return _part("ssh", target, False, str(err), err)


def run_test(args: argparse.Namespace) -> int:
    """Like the Settings screen's Connect button, plus an SSH login: report each part, fail if any fails."""
    store = _store()
    profile = _profile(store, args.name)
    bridge, notes = _test_bridge(profile, args)
    parts = [bridge] if args.no_ssh else [bridge, _test_ssh(profile, store, args)]
    ok = all(part["ok"] for part in parts)
    if ok:
        store.mark_used(profile.name)
    if args.json:
        print_json({"ok": ok, "profile": profile.name, "parts": parts, "notes": notes})
    else:
        for part in parts:
            print(f"{part['part']} {part['target']}: {'ok' if part['ok'] else 'FAILED'}: {part['detail']}")
            if part["part"] == "rosbridge":
                for note in notes:
                    print(f"note: {note}")
    return 0 if ok else 1
