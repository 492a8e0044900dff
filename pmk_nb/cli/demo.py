"""``pmk demo``: a simulated chair and the dashboard, ready to preview, in one command.

The first-run experience: converts the sample clinic floor into a demo maps folder, starts the
simulated chair (``pmk sim``) with an SFTP endpoint, writes a "Simulated chair" profile pointing at
it (SFTP by a key pair made in the demo folder), makes the clinic the current map and serves the
dashboard in kiosk mode with the Home preview starting by itself, so a new user opens the URL and
sees the chair patrolling without pressing anything.  Ctrl-C / SIGTERM stops everything.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path
from typing import TYPE_CHECKING

from pmk_nb.cli.options import Subparsers
from pmk_nb.cli.server_options import positive_int, server_options
from pmk_nb.serve import check_port_number, preflight, resolve_tls, serve_dashboard, sigterm_as_interrupt
from pmk_nb.ui import KIOSK_ENV

if TYPE_CHECKING:
    from pmk_nb.serve import TlsFiles


def add_parser(subparsers: Subparsers) -> None:
    """Register ``pmk demo``."""
    p = subparsers.add_parser(
        "demo",
        help="start a simulated chair and the dashboard, ready to preview",
        description="Convert the sample map, start a simulated chair and serve the dashboard in kiosk mode.",
    )
    server_options(p)
    p.add_argument("--demo-dir", dest="dir", type=Path, default=Path(".demo"), help="demo folder (default: ./.demo)")
    p.add_argument("--dir", dest="dir", type=Path, default=argparse.SUPPRESS, help=argparse.SUPPRESS)  # deprecated
    p.add_argument("--gml", type=Path, help="IndoorGML file to use (default: sample_maps/clinic_floor.gml)")
    p.add_argument("--no-kiosk", action="store_true", help="serve the full dashboard instead of the kiosk page")
    p.add_argument(
        "--classroom",
        action="store_true",
        help="a simulated chair per page, parked until its student drives it (teaching); no shared patrolling chair",
    )
    p.add_argument(
        "--max-chairs",
        type=positive_int,
        metavar="N",
        help="--classroom: refuse pages beyond N chairs at once (default: 5 a core, 300 MiB each of 3/4 of memory)",
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from pmk_nb.cli.demo_setup import prepare_demo

    check_port_number(args.port)
    # before the simulator starts: a refused --ip or a taken port fails fast
    token = preflight(args, dict(os.environ), kiosk=not args.no_kiosk)
    tls = resolve_tls(args, dict(os.environ))  # --https: kept in the user's config folder, not the demo's
    if args.classroom:
        return _run_classroom(args, token, tls)
    with sigterm_as_interrupt():
        print("Preparing the demo: converting the sample map, starting the simulated chair...", flush=True)
        demo = prepare_demo(args.dir, gml=args.gml)
        try:
            demo.env[KIOSK_ENV] = "0" if args.no_kiosk else "1"
            print(f"Simulated chair: rosbridge ws://127.0.0.1:{demo.ros_port}, SFTP port {demo.sftp_port}", flush=True)
            print("Open the URL below: the Home screen shows the chair patrolling the clinic.", flush=True)
            return serve_dashboard(args, demo.env, demo.root, token, tls)
        finally:
            demo.stop()


def _run_classroom(args: argparse.Namespace, token: str | None, tls: TlsFiles | None) -> int:
    """``pmk demo --classroom``: no shared chair; each page's kernel starts its own (issue 26)."""
    from pmk_nb.cli.demo_classroom import prepare_classroom

    with sigterm_as_interrupt():
        print("Preparing the classroom: converting the sample map...", flush=True)
        room = prepare_classroom(args.dir, gml=args.gml, max_chairs=args.max_chairs)
        room.env[KIOSK_ENV] = "0" if args.no_kiosk else "1"
        print(
            f"Classroom: every page gets its own simulated chair, parked until its student drives it "
            f"(at most {room.settings.max_chairs} at once; --max-chairs changes it).",
            flush=True,
        )
        return serve_dashboard(args, room.env, room.root, token, tls)
