"""``pmk dashboard``: serve the app as a Voilà kiosk page.

Voilà runs as a child process on a generated notebook (see :mod:`pmk_nb.serve.voila`); Ctrl-C or
SIGTERM stops it, and no child is left behind (:mod:`pmk_nb.serve.procs`).  ``--kiosk`` locks the
page down for a tablet on the chair (Home only, Maps and Settings behind a PIN, screen kept on).
``--https`` or ``--certfile/--keyfile`` serve it over TLS (:mod:`pmk_nb.serve.tablet_tls`), which a
LAN tablet needs for the kiosk's Screen Wake Lock; beyond loopback, plain HTTP needs ``--insecure``.
"""

from __future__ import annotations

import argparse
import os
import tempfile
from pathlib import Path

from pmk_nb.cli.options import Subparsers, add_maps_dir
from pmk_nb.cli.server_options import server_options
from pmk_nb.serve import check_port_number, preflight, resolve_tls, serve_dashboard, sigterm_as_interrupt
from pmk_nb.ui import AUTOSTART_ENV, KIOSK_ENV


def add_parser(subparsers: Subparsers) -> None:
    """Register ``pmk dashboard``."""
    p = subparsers.add_parser(
        "dashboard",
        help="serve the dashboard as a Voilà kiosk page",
        description="Serve the dashboard (Home, Maps, Settings) as a web page; Ctrl-C stops it.",
    )
    server_options(p)
    add_maps_dir(p)
    p.add_argument("--config-dir", type=Path, help="settings folder (default: $PMK_CONFIG_DIR or user config)")
    p.add_argument(
        "--preview-on-start",
        action="store_true",
        help="start the Home screen's live preview by itself (kiosk: no button to press)",
    )
    p.add_argument(
        "--kiosk",
        action="store_true",
        help="locked-down tablet page: Home only with big buttons, Maps and Settings behind the PIN set in "
        "Settings, screen kept on, a token even on loopback (printed in the URL); implies --preview-on-start",
    )
    p.add_argument(
        "--allow-local",
        action="store_true",
        help="let the Maps screen download from loopback and LAN addresses (a lab server); refused by default",
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    check_port_number(args.port)
    env = dict(os.environ)
    if args.maps_dir is not None:
        env["PMK_MAPS_DIR"] = str(args.maps_dir.expanduser().resolve())
    if args.config_dir is not None:
        env["PMK_CONFIG_DIR"] = str(args.config_dir.expanduser().resolve())
    if args.preview_on_start or args.kiosk:
        env[AUTOSTART_ENV] = "1"
    env[KIOSK_ENV] = "1" if args.kiosk else "0"
    from pmk_nb.library import ALLOW_LOCAL_ENV  # here: the HTTP modules stay out of `pmk --help`

    env[ALLOW_LOCAL_ENV] = "1" if getattr(args, "allow_local", False) else "0"
    token = preflight(args, env, kiosk=args.kiosk)
    tls = resolve_tls(args, env)
    with sigterm_as_interrupt(), tempfile.TemporaryDirectory(prefix="pmk-dashboard-") as tmp:
        return serve_dashboard(args, env, Path(tmp), token, tls)
