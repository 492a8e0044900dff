"""A running class hub's processes: is it up (through its proxy), stop it, end what it left behind.

``pmk hub`` starts JupyterHub (:mod:`pmk_nb.cli.hub`); these wait for it, stop it with the signal that
makes it stop its students' servers and the proxy, and end any process of the class still alive.
"""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import time
from pathlib import Path
from typing import Any

from pmk_nb.serve.procs import ProcessStartError, stop_process

HUB_STOP_TIMEOUT = 30.0


def wait_until_healthy(url: str, hub: subprocess.Popen[Any], timeout: float) -> None:
    """Until the hub answers through its proxy (``hub/health``): the proxy listens before its route exists.

    Raises:
        ProcessStartError: the hub exited or did not answer in time.
    """
    import ssl
    import urllib.error
    import urllib.parse
    import urllib.request

    context = ssl.create_default_context()  # our own loopback hub, maybe on a self-signed certificate:
    context.check_hostname, context.verify_mode = False, ssl.CERT_NONE  # not verified (it is ours)
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and hub.poll() is None:
        with (
            contextlib.suppress(OSError, urllib.error.URLError),
            urllib.request.urlopen(f"{url}hub/health", timeout=5, context=context) as answer,
        ):
            if answer.status == 200:
                return
        time.sleep(0.3)
    where = urllib.parse.urlsplit(url)
    raise ProcessStartError("JupyterHub (its health page)", where.hostname or "", where.port or 0, hub.poll(), timeout)


def stop_hub(hub: subprocess.Popen[Any]) -> None:
    """SIGINT (JupyterHub then stops the students' servers and the proxy), SIGTERM/SIGKILL if it hangs."""
    if hub.poll() is None:
        hub.send_signal(signal.SIGINT)
        try:
            hub.wait(timeout=HUB_STOP_TIMEOUT)
        except subprocess.TimeoutExpired:
            stop_process(hub)


def end_class_processes(classroom_file: Path, state_dir: Path) -> int:
    """End what the hub left: processes with this class in their environment (students' servers,
    their kernels) and the proxy of its pid file; returns how many were still alive."""
    marker = f"PMK_CLASSROOM={classroom_file}".encode()
    pids = []
    for proc in Path("/proc").iterdir():
        if proc.name.isdigit() and int(proc.name) != os.getpid():
            with contextlib.suppress(OSError):
                if marker in (proc / "environ").read_bytes().split(b"\0"):
                    pids.append(int(proc.name))
    with contextlib.suppress(OSError, ValueError):
        pid = int((state_dir / "jupyterhub-proxy.pid").read_text().strip())
        if b"configurable-http-proxy" in Path(f"/proc/{pid}/cmdline").read_bytes():
            pids.append(pid)
    for sig in (signal.SIGTERM, signal.SIGKILL):
        alive = [p for p in pids if _signal(p, sig)]
        deadline = time.monotonic() + 5.0
        while alive and time.monotonic() < deadline and any(Path(f"/proc/{p}").exists() for p in alive):
            time.sleep(0.1)
    return len(pids)


def _signal(pid: int, sig: int) -> bool:
    try:
        os.kill(pid, sig)
    except (ProcessLookupError, PermissionError):
        return False
    return True
