"""``pmk sim``: run a simulated chair (rosbridge v2 + SFTP) until Ctrl-C or SIGTERM."""

from __future__ import annotations

import argparse
import contextlib
import math
import signal
import tempfile
import threading
from pathlib import Path

from pmk_nb.cli.options import Subparsers, add_maps_dir
from pmk_nb.sim import (
    BRIDGE_MODES,
    DEFAULT_BRIDGE,
    ROS_VERSIONS,
    SimChair,
    SimConfig,
    SimError,
    default_state_dir,
    sample_floor,
)

READY_LINE = "pmk sim: ready"


def add_parser(subparsers: Subparsers) -> None:
    p = subparsers.add_parser(
        "sim",
        help="run a simulated chair: rosbridge v2 on a WebSocket, map server with hot reload, SFTP",
        description="Simulated PMK wheelchair for demos and tests (loopback only by default).",
    )
    p.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1)")
    p.add_argument("--port", type=int, default=9090, help="rosbridge WebSocket port (0 = any free port)")
    p.add_argument(
        "--map",
        type=Path,
        default=None,
        help="map_server YAML to start with (default: sample clinic floor, else a built-in demo floor)",
    )
    add_maps_dir(p, help="the chair's ~/ALMA_MAPS folder (default: temp)")
    p.add_argument(
        "--state-dir",
        type=Path,
        default=None,
        help="where the chair's SSH host key is kept, so a restart keeps it (default: $PMK_SIM_STATE_DIR or "
        "the user state folder)",
    )
    p.add_argument("--sftp-port", type=int, default=2222, help="SFTP port (0 = any free port)")
    p.add_argument("--no-sftp", action="store_true", help="do not start the SFTP endpoint")
    p.add_argument("--sftp-user", default="pmk", help="SFTP login name (default pmk)")
    p.add_argument("--sftp-password", default=None, help="default: a random password, printed at start")
    p.add_argument(
        "--sftp-authorized-key",
        type=Path,
        default=None,
        metavar="PATH",
        help="OpenSSH public key file (e.g. ~/.ssh/id_ed25519.pub, or an authorized_keys file) whose keys may "
        "log in as --sftp-user; password login stays on as well unless --no-sftp-password",
    )
    p.add_argument(
        "--no-sftp-password",
        action="store_true",
        help="refuse password login (key only, like a hardened chair); needs --sftp-authorized-key, "
        "conflicts with --sftp-password",
    )
    p.add_argument(
        "--ros", choices=ROS_VERSIONS, default="ros1", help="message spelling the chair speaks (default ros1)"
    )
    p.add_argument("--flavour", dest="ros", choices=ROS_VERSIONS, default=argparse.SUPPRESS, help=argparse.SUPPRESS)
    p.add_argument(
        "--bridge",
        choices=BRIDGE_MODES,
        default=DEFAULT_BRIDGE,
        help=f"which rosbridge's ROS 2 action-goal behaviour to reproduce (default {DEFAULT_BRIDGE}: rosbridge_suite "
        "2.1.0, which keeps a lost client's goals, never answers a rejected goal and handles a cancel only "
        "after the goal; rs: rosbridge-server-rs)",
    )
    p.add_argument("--odom-rate", type=float, default=50.0, help="Hz")
    p.add_argument("--scan-rate", type=float, default=20.0, help="Hz")
    p.add_argument("--rays", type=int, default=720, help="laser rays over 270 degrees")
    p.add_argument(
        "--laser-range",
        type=_positive_metres,
        default=10.0,
        metavar="METRES",
        help="laser range_max (default 10); rays that hit nothing within it report +inf, sent as null",
    )
    p.add_argument("--patrol", action="store_true", help="drive between random reachable points forever")
    p.add_argument(
        "--laser-blind",
        type=_sector,
        default=None,
        metavar="FROM:TO",
        help="degrees (0 = ahead, + = left) where the laser is blind and reports NaN, e.g. --laser-blind=-20:40",
    )
    _add_tls_options(p)
    p.set_defaults(run=run)


def _add_tls_options(p: argparse.ArgumentParser) -> None:
    """wss:// as rosbridge_suite serves it with its certfile/keyfile parameters (issue 24)."""
    p.add_argument("--certfile", type=Path, default=None, help="serve wss:// with this PEM certificate")
    p.add_argument("--keyfile", type=Path, default=None, help="the certificate's private key (PEM)")
    p.add_argument(
        "--tls",
        action="store_true",
        help="serve wss:// with a throwaway self-signed certificate (its SHA-256 fingerprint is printed)",
    )


def _tls_files(args: argparse.Namespace, stack: contextlib.ExitStack) -> tuple[Path, Path] | None:
    if (args.certfile is None) != (args.keyfile is None):
        raise SimError("--certfile and --keyfile go together: give both, or --tls for a throwaway certificate")
    if args.certfile is not None:
        if args.tls:
            raise SimError("--tls makes its own certificate: give it, or --certfile/--keyfile, not both")
        return args.certfile.expanduser(), args.keyfile.expanduser()
    if not args.tls:
        return None
    from pmk_nb.tlscert import write_self_signed

    folder = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="pmk-sim-tls-")))
    names = [args.host] + [n for n in ("localhost", "127.0.0.1") if n != args.host]
    return write_self_signed(folder, names)


def describe(sim: SimChair) -> list[str]:
    """The lines ``pmk sim`` prints: where to connect and what is served."""
    bridge = sim.bridge
    assert bridge is not None and sim.grid is not None
    grid = sim.grid
    lines = [
        f"pmk sim: rosbridge v2 ({sim.config.ros}, bridge {sim.config.bridge}) at {sim.url}",
        f"  map: {_map_name(sim)} ({grid.width}x{grid.height} cells, {grid.resolution:.3f} m/cell)",
        "  chair at x={:.2f} y={:.2f} theta={:.2f}".format(*sim.pose),
        f"  maps dir (chair ~/ALMA_MAPS): {sim.maps_dir}",
        "  topics:",
    ]
    lines += [f"    {name} [{entry.type}]" for name, entry in sorted(bridge.topics.items())]
    lines.append("  services:")
    lines += [f"    {name} [{entry.type}]" for name, entry in sorted(bridge.services.items())]
    if sim.sftp_port is not None:
        login = f"password {sim.sftp_password}" if sim.sftp_password is not None else "key login only"
        lines.append(f"  sftp: {sim.config.sftp_user}@{sim.config.host} port {sim.sftp_port} {login}")
        if sim.config.sftp_authorized_key is not None:
            prints = ", ".join(sim.sftp_authorized_fingerprints)
            lines.append(f"  sftp authorized keys: {prints} (from {sim.config.sftp_authorized_key})")
        lines.append(f"  sftp host key: {sim.sftp_host_key_fingerprint} ({sim.sftp_host_key})")
    if sim.tls is not None:
        from pmk_nb.tlscert import file_fingerprint

        lines.append(f"  tls certificate: SHA-256 {file_fingerprint(sim.tls[0])} ({sim.tls[0]})")
    return lines


def _map_name(sim: SimChair) -> str:
    if sim.mapserver is not None and sim.mapserver.source is not None:
        return str(sim.mapserver.source)
    grid = sim.grid
    source = grid.meta.get("source") if grid is not None else None
    return f"sample {source}" if source and source != "demo" else "built-in demo floor"


def _check_sftp_args(args: argparse.Namespace) -> None:
    if not args.no_sftp_password:
        return
    if args.sftp_authorized_key is None:
        raise SimError("--no-sftp-password needs --sftp-authorized-key PATH, or nobody could log in over SFTP")
    if args.sftp_password is not None:
        raise SimError("--no-sftp-password and --sftp-password contradict each other: give one of them")


def _sector(text: str) -> tuple[float, float]:
    """``FROM:TO`` in degrees -> (from, to) in radians."""
    try:
        lo, hi = (math.radians(float(part)) for part in text.split(":"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: give two angles in degrees as FROM:TO, e.g. -20:40") from None
    return lo, hi


def _positive_metres(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"{text!r}: give a range in metres above 0, e.g. 10")
    return value


def run(args: argparse.Namespace) -> int:
    _check_sftp_args(args)
    with contextlib.ExitStack() as stack:
        return _serve(args, _tls_files(args, stack))


def _serve(args: argparse.Namespace, tls: tuple[Path, Path] | None) -> int:
    grid = None if args.map is not None else sample_floor()
    config = SimConfig(
        map_yaml=args.map,
        grid=grid,
        host=args.host,
        port=args.port,
        ros=args.ros,
        odom_rate=args.odom_rate,
        scan_rate=args.scan_rate,
        rays=args.rays,
        patrol=args.patrol,
        laser_blind=args.laser_blind,
        range_max=args.laser_range,
        sftp_port=None if args.no_sftp else args.sftp_port,
        sftp_user=args.sftp_user,
        sftp_password=args.sftp_password,
        sftp_authorized_key=args.sftp_authorized_key.expanduser() if args.sftp_authorized_key else None,
        sftp_password_login=not args.no_sftp_password,
        maps_dir=args.maps_dir,
        tls=tls,
        bridge=args.bridge,
        state_dir=args.state_dir if args.state_dir is not None else default_state_dir(),
    )
    sim = SimChair(config)
    stop = threading.Event()
    previous = {sig: signal.signal(sig, lambda *_: stop.set()) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        sim.start()
        for line in describe(sim):
            print(line, flush=True)
        print(f"{READY_LINE} (Ctrl-C to stop)", flush=True)
        while not stop.wait(0.5):
            if not sim.running:
                print("pmk sim: the simulator thread ended unexpectedly", flush=True)
                return 1
    finally:
        sim.stop()
        for sig, handler in previous.items():
            signal.signal(sig, handler)
    print("pmk sim: stopped", flush=True)
    return 0
