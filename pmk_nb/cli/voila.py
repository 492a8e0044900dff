"""How the dashboard is served as a Voilà kiosk page: the notebook it runs and the server options.

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

import json
import sys
from pathlib import Path

DASHBOARD_SOURCE = "from pmk_nb.ui import build_app\n\nbuild_app()"
DASHBOARD_TITLE = "PMK Wheelchair"
CULL_IDLE_TIMEOUT = 600
CULL_INTERVAL = 60
DEFAULT_PORT = 8866
DEFAULT_IP = "127.0.0.1"


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
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / "dashboard.ipynb"
    tmp = path.with_suffix(".ipynb.tmp")
    tmp.write_text(json.dumps(dashboard_notebook(), indent=1) + "\n", encoding="utf-8")
    tmp.replace(path)
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
