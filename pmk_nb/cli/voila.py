"""How the dashboard is served as a Voilà kiosk page: the notebook it runs, the server options, serve().

The kiosk notebook is generated (a pip-installed package has no ``notebooks/`` folder) with the same
two lines as ``notebooks/dashboard.ipynb``; a test keeps the two identical.

Server choices, and why:
  * ``--strip_sources=True``: the page shows the app, never code.
  * ``--Voila.ip=127.0.0.1`` by default: a kiosk on another device must be opted into (``--ip``).
  * ``MappingKernelManager.cull_idle_timeout=600`` / ``cull_interval=60``: a page closed without its
    ``beforeunload`` shutdown (tablet asleep, browser killed) leaves a kernel holding a chair
    connection; it is culled after 10 idle minutes.  ``cull_connected`` stays False so an open
    kiosk page is never killed under its user.
  * ``show_tracebacks`` stays False: the app reports errors itself.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

from pmk_nb.cli.procs import stop_process, wait_children, wait_for_port
from pmk_nb.fileio import atomic_write

DASHBOARD_SOURCE = "from pmk_nb.ui import build_app\n\nbuild_app()"
DASHBOARD_TITLE = "PMK Wheelchair"
CULL_IDLE_TIMEOUT = 600
CULL_INTERVAL = 60
DEFAULT_PORT = 8866
DEFAULT_IP = "127.0.0.1"
VOILA_START_TIMEOUT = 120.0


def dashboard_notebook() -> dict[str, object]:
    """The kiosk notebook as nbformat 4 JSON: one code cell (no title: the app has its own), python3."""
    return {
        "cells": [
            {
                "cell_type": "code",
                "execution_count": None,
                "id": "pmk-app",
                "metadata": {},
                "outputs": [],
                "source": DASHBOARD_SOURCE,
            },
        ],
        "metadata": {
            "kernelspec": {"display_name": "Python 3 (ipykernel)", "language": "python", "name": "python3"},
            "language_info": {"name": "python"},
            "title": DASHBOARD_TITLE,
        },
        "nbformat": 4,
        "nbformat_minor": 5,
    }


def write_dashboard_notebook(directory: Path) -> Path:
    """Write ``dashboard.ipynb`` into ``directory`` (created) and return its path."""
    path = directory / "dashboard.ipynb"
    atomic_write(path, json.dumps(dashboard_notebook(), indent=1) + "\n", mkdir=True)
    return path


def voila_command(
    notebook: Path,
    *,
    port: int = DEFAULT_PORT,
    ip: str = DEFAULT_IP,
    open_browser: bool = False,
    cull_idle_timeout: int = CULL_IDLE_TIMEOUT,
    cull_interval: int = CULL_INTERVAL,
) -> list[str]:
    """The command line that serves ``notebook`` with this interpreter's Voilà."""
    cmd = [
        sys.executable,
        "-m",
        "voila",
        str(notebook),
        f"--port={int(port)}",
        f"--Voila.ip={ip}",
        "--strip_sources=True",
        "--theme=light",
        f"--MappingKernelManager.cull_idle_timeout={int(cull_idle_timeout)}",
        f"--MappingKernelManager.cull_interval={int(cull_interval)}",
        "--MappingKernelManager.cull_connected=False",
        "--VoilaConfiguration.show_tracebacks=False",
    ]
    if not open_browser:
        cmd.append("--no-browser")
    return cmd


def server_options(p: argparse.ArgumentParser) -> None:
    """``--port``, ``--ip``, ``--no-browser``: the options of every command that serves the dashboard."""
    p.add_argument("--port", type=int, default=DEFAULT_PORT, help=f"HTTP port (default {DEFAULT_PORT})")
    p.add_argument(
        "--ip",
        default=DEFAULT_IP,
        help=f"address to listen on (default {DEFAULT_IP}; use 0.0.0.0 to serve a tablet on the LAN)",
    )
    p.add_argument("--no-browser", action="store_true", help="do not open a browser")


def _local_host(ip: str) -> str:
    """Where this machine reaches a server listening on ``ip`` (all interfaces -> loopback)."""
    return "127.0.0.1" if ip in ("0.0.0.0", "") else ip


def serve(args: argparse.Namespace, env: dict[str, str], workdir: Path) -> int:
    """Start Voilà on the generated notebook, print the URL, wait until it ends or we are stopped."""
    notebook = write_dashboard_notebook(workdir)
    cmd = voila_command(notebook, port=args.port, ip=args.ip, open_browser=not args.no_browser)
    voila = subprocess.Popen(cmd, env=env, cwd=workdir)
    try:
        wait_for_port(_local_host(args.ip), args.port, voila, "Voilà", VOILA_START_TIMEOUT)
        print(f"PMK dashboard: http://{_local_host(args.ip)}:{args.port}/  (Ctrl-C to stop)", flush=True)
        return wait_children([voila])
    finally:
        stop_process(voila)
