"""``pmk dashboard``: serve the app as a Voilà kiosk page.

Voilà runs as a child process on a generated notebook (see :mod:`pmk_nb.cli.voila`); Ctrl-C or
SIGTERM stops it, and no child is left behind (:mod:`pmk_nb.cli.procs`).
"""

from __future__ import annotations

import argparse
import os
import tempfile
from pathlib import Path
from typing import Any

from pmk_nb.cli.procs import check_port_number, sigterm_as_interrupt
from pmk_nb.cli.voila import serve, server_options
from pmk_nb.ui.context import AUTOSTART_ENV


def add_parser(subparsers: Any) -> None:
    """Register ``pmk dashboard``."""
    p = subparsers.add_parser("dashboard", help="serve the dashboard as a Voilà kiosk page")
    server_options(p)
    p.add_argument("--maps-dir", type=Path, help="maps folder (default: $PMK_MAPS_DIR or the user data dir)")
    p.add_argument("--config-dir", type=Path, help="settings folder (default: $PMK_CONFIG_DIR or user config)")
    p.add_argument(
        "--preview-on-start",
        action="store_true",
        help="start the Home screen's live preview by itself (kiosk: no button to press)",
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    check_port_number(args.port)
    env = dict(os.environ)
    if args.maps_dir is not None:
        env["PMK_MAPS_DIR"] = str(args.maps_dir.expanduser().resolve())
    if args.config_dir is not None:
        env["PMK_CONFIG_DIR"] = str(args.config_dir.expanduser().resolve())
    if args.preview_on_start:
        env[AUTOSTART_ENV] = "1"
    with sigterm_as_interrupt(), tempfile.TemporaryDirectory(prefix="pmk-dashboard-") as tmp:
        return serve(args, env, Path(tmp))
