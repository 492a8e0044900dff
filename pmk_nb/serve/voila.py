"""How the dashboard is served as a Voilà kiosk page: the notebook it runs, its configuration, serve_dashboard().

The kiosk notebook is generated (a pip-installed package has no ``notebooks/`` folder) with the same
two lines as ``notebooks/dashboard.ipynb``; a test keeps the two identical.  Beside it goes the
server's config file ``voila.json`` (Voilà reads only that folder's config, so a user's own Jupyter
config cannot undo these choices); it holds what cannot travel on a command line: integer tornado
settings and the access token (a command line is visible to every local user).

Server choices, and why:
  * ``--strip_sources=True``: the page shows the app, never code.
  * ``--Voila.ip=127.0.0.1`` by default: a kiosk on another device must be opted into (``--ip``),
    and then only with a token (:func:`check_serving`).
  * ``--Voila.port_retries=0``: Voilà would otherwise move to the next free port by itself while we
    print the one asked for; a taken port is a clear error instead (:func:`check_port_free`).
  * Kernels end with their page (:mod:`pmk_nb.serve.voila_kernels`): the kernel manager shuts a kernel
    down a few seconds after its page's websocket closed, and websocket pings every second close a
    connection whose tablet went to sleep.  Idle culling stays as a back-stop and now also culls
    connected kernels: a live page answers the page heartbeat every 2 s (see
    :mod:`pmk_nb.ui.common.page_lifecycle`), so only a kernel whose page stopped pinging ever looks idle.
  * HTTPS (issue 24) when a certificate is given or made (:mod:`pmk_nb.serve.tablet_tls`): Voilà is
    then started as :mod:`pmk_nb.serve.voila_tls` with ``ssl_options`` in ``voila.json``; beyond
    loopback, plain HTTP needs ``--insecure`` (:func:`pmk_nb.serve.serving.check_transport`).
  * ``show_tracebacks`` stays False: the app reports errors itself.
  * Tokens are masked in the server's log (``?token=***``): tornado logs each 4xx with its URL
    (:mod:`pmk_nb.serve.tokenmask`).
  * Only this server's own names are served (Host and Origin checked, token or not), a kernel has
    one websocket (its page's, binary protocol, bounded output), see :mod:`pmk_nb.serve.voila_guard`;
    a kiosk always requires a token, on loopback too (:func:`preflight`).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import webbrowser
from pathlib import Path
from typing import TYPE_CHECKING

from pmk_nb.fileio import atomic_write
from pmk_nb.serve import serving, tokenmask
from pmk_nb.serve.procs import stop_process, wait_children, wait_for_port
from pmk_nb.serve.voila_kernels import WS_PING_INTERVAL_MS, WS_PING_TIMEOUT_MS

if TYPE_CHECKING:
    from pmk_nb.serve.tablet_tls import TlsFiles

DASHBOARD_SOURCE = "from pmk_nb.ui import build_app\n\nbuild_app()"
DASHBOARD_TITLE = "PMK Wheelchair"
CULL_IDLE_TIMEOUT = 300
CULL_INTERVAL = 30
DEFAULT_PORT = serving.DEFAULT_PORT
DEFAULT_IP = serving.DEFAULT_IP
VOILA_START_TIMEOUT = 120.0
KERNEL_MANAGER = "pmk_nb.serve.voila_kernels.PageBoundKernelManager"
IDENTITY_PROVIDER = "pmk_nb.serve.voila_guard.HostCheckingIdentityProvider"
KERNEL_CONNECTION = "pmk_nb.serve.voila_guard.PageChannelConnection"
CONFIG_FILE = "voila.json"
#: seconds Voilà waits for the notebook's output while rendering a page (nbclient's default, 4 s, on a
#: loaded machine drops the app's output: "Timeout waiting for IOPub output" and a blank page)
IOPUB_TIMEOUT = 60
#: the largest message a page may send its kernel: a file chosen on the device (an IndoorGML plan, an
#: MCAP recording, up to 200 MB each) travels as one; tornado's default, 10 MiB, closed the page's
#: socket on anything larger (the page then lost its kernel, and said nothing)
MAX_PAGE_MESSAGE_BYTES = 210 * 2**20


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


def server_config(token: str | None = None, ip: str = DEFAULT_IP, tls: TlsFiles | None = None) -> dict[str, object]:
    """Voilà's config file: websocket pings (integers, which the command line would make strings), the
    largest message a page may send (an uploaded file), token,
    the guards of :mod:`pmk_nb.serve.voila_guard` (Host/Origin for ``ip``, one bounded channel per kernel),
    the certificate to serve HTTPS with (read by :mod:`pmk_nb.serve.voila_tls`), tokens masked in its log
    (:mod:`pmk_nb.serve.tokenmask`)."""
    tornado: dict[str, object] = {
        "ws_ping_interval": WS_PING_INTERVAL_MS,
        "ws_ping_timeout": WS_PING_TIMEOUT_MS,
        "websocket_max_message_size": MAX_PAGE_MESSAGE_BYTES,
    }
    if tls is not None:
        tornado["ssl_options"] = {"certfile": str(tls.certfile), "keyfile": str(tls.keyfile)}
    if serving.is_loopback(ip):  # jupyter_server's own Host check as well (it knows loopback names only)
        # ... and the names the served certificate vouches for (voila_guard accepts them too)
        names = ["localhost", *(n for n in (tls.names if tls else ()) if not serving.is_ip_address(n))]
        tornado.update(allow_remote_access=False, local_hostnames=list(dict.fromkeys(names)))
    voila: dict[str, object] = {
        "tornado_settings": tornado,
        "identity_provider_class": IDENTITY_PROVIDER,
        "kernel_websocket_connection_class": KERNEL_CONNECTION,
        "logging_config": tokenmask.logging_config(),
    }
    if token:
        voila["token"] = token
    return {"Voila": voila}


def write_dashboard_notebook(
    directory: Path, *, token: str | None = None, ip: str = DEFAULT_IP, tls: TlsFiles | None = None
) -> Path:
    """Write ``dashboard.ipynb`` and the server's ``voila.json`` (0600) into ``directory``; return the notebook."""
    path = directory / "dashboard.ipynb"
    atomic_write(path, json.dumps(dashboard_notebook(), indent=1) + "\n", mkdir=True)
    config = json.dumps(server_config(token, ip, tls), indent=1) + "\n"
    atomic_write(directory / CONFIG_FILE, config, mode=0o600)
    return path


def voila_command(
    notebook: Path,
    *,
    port: int = DEFAULT_PORT,
    ip: str = DEFAULT_IP,
    open_browser: bool = False,
    cull_idle_timeout: int = CULL_IDLE_TIMEOUT,
    cull_interval: int = CULL_INTERVAL,
    tls: bool = False,
) -> list[str]:
    """The command line that serves ``notebook`` with this interpreter's Voilà (config: beside the notebook);
    ``tls``: Voilà with HTTPS (:mod:`pmk_nb.serve.voila_tls`; the certificate is in the config)."""
    cmd = [
        sys.executable,
        "-m",
        "pmk_nb.serve.voila_tls" if tls else "voila",
        str(notebook),
        f"--port={int(port)}",
        "--Voila.port_retries=0",
        f"--Voila.ip={ip}",
        f"--Voila.config_file_paths={notebook.parent}",
        "--strip_sources=True",
        "--theme=light",
        f"--VoilaConfiguration.multi_kernel_manager_class={KERNEL_MANAGER}",
        f"--MappingKernelManager.cull_idle_timeout={int(cull_idle_timeout)}",
        f"--MappingKernelManager.cull_interval={int(cull_interval)}",
        "--MappingKernelManager.cull_connected=True",
        "--VoilaConfiguration.show_tracebacks=False",
        f"--VoilaExecutor.iopub_timeout={IOPUB_TIMEOUT}",
    ]
    if not open_browser:
        cmd.append("--no-browser")
    return cmd


def preflight(args: argparse.Namespace, env: dict[str, str], *, kiosk: bool = False) -> str | None:
    """Check ``--ip``/``--token``/``--port`` before anything starts; return the token to require (or None).

    A kiosk gets a random token when none is given, on loopback too: its page can move the chair, and
    any local program or web page (DNS rebinding) could otherwise open it.

    Raises:
        ServingRefused: beyond loopback without a token, a short token, plain HTTP beyond loopback
            without ``--insecure``, or the port is taken.
    """
    from pmk_nb.serve.tablet_tls import wants_tls

    token = serving.resolve_token(args.token, env)
    if kiosk and not token:
        token = serving.resolve_token(serving.AUTO_TOKEN, env)
    serving.check_serving(args.ip, token)
    serving.check_transport(args.ip, tls=wants_tls(args), insecure=bool(getattr(args, "insecure", False)))
    serving.check_port_free(args.ip, args.port)
    return token


def serve_dashboard(
    args: argparse.Namespace, env: dict[str, str], workdir: Path, token: str | None, tls: TlsFiles | None = None
) -> int:
    """Start Voilà on the generated notebook, print the URL it really serves, wait until it ends or we are stopped.

    ``token`` comes from :func:`preflight`, ``tls`` from :func:`pmk_nb.serve.tablet_tls.resolve_tls`; the port
    is checked again (something may have taken it meanwhile).
    """
    serving.check_port_free(args.ip, args.port)
    notebook = write_dashboard_notebook(workdir, token=token, ip=args.ip, tls=tls)
    # Voilà would open its URL without the token (a login page): with one, we open the right URL ourselves
    cmd = voila_command(
        notebook, port=args.port, ip=args.ip, open_browser=not args.no_browser and not token, tls=tls is not None
    )
    voila = subprocess.Popen(cmd, env=env, cwd=workdir)
    scheme = "https" if tls else "http"
    try:
        wait_for_port(serving.local_host(args.ip), args.port, voila, "Voilà", VOILA_START_TIMEOUT)
        for line in serving.url_lines(args.ip, args.port, token, scheme) + tls_lines(args.ip, args.port, token, tls):
            print(line, flush=True)
        if token and not args.no_browser:
            webbrowser.open(serving.dashboard_url(serving.local_host(args.ip), args.port, token, scheme))
        return wait_children([voila])
    finally:
        stop_process(voila)
        (workdir / CONFIG_FILE).unlink(missing_ok=True)  # it holds the token


def tls_lines(ip: str, port: int, token: str | None, tls: TlsFiles | None, *, color: bool | None = None) -> list[str]:
    """What ``pmk dashboard`` prints after the URLs: the certificate's fingerprint (and the authority to
    trust on the tablet) over HTTPS; beyond loopback, a QR code of the tablet's URL with its token."""
    lines = []
    if tls is not None:
        # a new one: a tablet that checked the old fingerprint (and trusts no authority) must check again
        lines.append(f"  {'new ' if tls.created else ''}certificate SHA-256: {tls.fingerprint}")
        if tls.ca_file is not None:
            trust = (
                "a new authority to trust on the tablet (again)"
                if tls.replaced_authority
                else "to trust on the tablet (once)"
            )
            lines.append(f"  {trust}: {tls.ca_file}  SHA-256 {tls.ca_fingerprint}")
    url = serving.tablet_url(ip, port, token, "https" if tls else "http")
    if url is not None:
        lines.append(f"  scan on the tablet: {url}")
        lines += serving.qr_lines(url, color=sys.stdout.isatty() if color is None else color)
    return lines
