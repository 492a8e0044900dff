"""``pmk dashboard``: serve the app as a Voilà kiosk page, plus the process helpers ``pmk demo`` shares.

Voilà runs as a child process on a generated notebook (see :mod:`pmk_nb.cli.voila`); Ctrl-C or
SIGTERM stops it, and no child is left behind.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from pmk_nb.cli.voila import DEFAULT_IP, DEFAULT_PORT, voila_command, write_dashboard_notebook
from pmk_nb.errors import PmkError
from pmk_nb.ui.context import AUTOSTART_ENV

VOILA_START_TIMEOUT = 120.0


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


def server_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--port", type=int, default=DEFAULT_PORT, help=f"HTTP port (default {DEFAULT_PORT})")
    p.add_argument(
        "--ip",
        default=DEFAULT_IP,
        help=f"address to listen on (default {DEFAULT_IP}; use 0.0.0.0 to serve a tablet on the LAN)",
    )
    p.add_argument("--no-browser", action="store_true", help="do not open a browser")


def free_port(host: str = "127.0.0.1") -> int:
    """A TCP port free right now on ``host`` (bind to port 0)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind((host, 0))
        return int(sock.getsockname()[1])


def wait_for_port(host: str, port: int, proc: subprocess.Popen[Any], what: str, timeout: float) -> None:
    """Wait until ``proc`` accepts TCP connections on ``port``; raise PmkError if it dies or times out."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            raise PmkError(f"{what} exited with code {proc.returncode} before listening on {host}:{port}")
        with contextlib.suppress(OSError), socket.create_connection((host, port), timeout=0.5):
            return
        time.sleep(0.2)
    raise PmkError(f"{what} did not listen on {host}:{port} within {timeout:.0f} s")


def stop_process(proc: subprocess.Popen[Any] | None, timeout: float = 10.0) -> None:
    """SIGTERM, then SIGKILL after ``timeout`` s: leave no child behind."""
    if proc is None or proc.poll() is not None:
        return
    proc.terminate()
    try:
        proc.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait(timeout=timeout)


def check_port_number(port: int) -> None:
    if not 1 <= port <= 65535:
        raise PmkError(f"--port {port}: give a port number between 1 and 65535")


def _url(ip: str, port: int) -> str:
    host = "127.0.0.1" if ip in ("0.0.0.0", "") else ip
    return f"http://{host}:{port}/"


def serve(args: argparse.Namespace, env: dict[str, str], workdir: Path) -> int:
    """Start Voilà on the generated notebook, print the URL, wait until it ends or we are stopped."""
    notebook = write_dashboard_notebook(workdir)
    cmd = voila_command(notebook, port=args.port, ip=args.ip, open_browser=not args.no_browser)
    voila = subprocess.Popen(cmd, env=env, cwd=workdir)
    try:
        wait_for_port(
            "127.0.0.1" if args.ip in ("0.0.0.0", "") else args.ip, args.port, voila, "Voilà", VOILA_START_TIMEOUT
        )
        print(f"PMK dashboard: {_url(args.ip, args.port)}  (Ctrl-C to stop)", flush=True)
        return _wait_children([voila])
    finally:
        stop_process(voila)


def _wait_children(procs: list[subprocess.Popen[Any]]) -> int:
    while True:
        for proc in procs:
            code = proc.poll()
            if code is not None:
                print(f"pmk: {proc.args[3] if len(proc.args) > 3 else proc.args} exited ({code})", file=sys.stderr)
                return 1 if code else 0
        time.sleep(0.5)


@contextlib.contextmanager
def sigterm_as_interrupt() -> Any:
    """Turn SIGTERM into KeyboardInterrupt so `finally` blocks stop the children."""

    def handler(_signum: int, _frame: object) -> None:
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGTERM, handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


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
