"""Child-process helpers shared by ``pmk dashboard``, ``pmk demo`` and the tests that start servers.

The CLI starts servers (Voilà, ``pmk sim``) as child processes; these helpers find a port, wait
until a child listens, and make sure no child outlives Ctrl-C or SIGTERM.
"""

from __future__ import annotations

import contextlib
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator, Sequence
from typing import Any

from pmk_nb.errors import PmkError


class ProcessStartError(PmkError):
    """A child process died or never listened on its port.

    Attributes:
        what: the child, in words ("Voilà", "the simulated chair (SFTP)").
        host, port: where it should have listened.
        returncode: its exit code if it died, None if it was still running when time ran out.
        timeout: the seconds waited.
    """

    def __init__(self, what: str, host: str, port: int, returncode: int | None, timeout: float) -> None:
        if returncode is not None:
            message = f"{what} exited with code {returncode} before listening on {host}:{port}"
        else:
            message = f"{what} did not listen on {host}:{port} within {timeout:.0f} s"
        super().__init__(message)
        self.what, self.host, self.port, self.returncode, self.timeout = what, host, port, returncode, timeout


def free_port(host: str = "127.0.0.1") -> int:
    """A TCP port free right now on ``host`` (bind to port 0)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind((host, 0))
        return int(sock.getsockname()[1])


def check_port_number(port: int) -> None:
    """Refuse a ``--port`` outside 1..65535 before any child is started."""
    if not 1 <= port <= 65535:
        raise PmkError(f"--port {port}: give a port number between 1 and 65535")


def wait_for_port(host: str, port: int, proc: subprocess.Popen[Any], what: str, timeout: float) -> None:
    """Wait until ``proc`` accepts TCP connections on ``port``.

    Raises:
        ProcessStartError: ``proc`` exited first, or ``timeout`` s passed.
    """
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            raise ProcessStartError(what, host, port, proc.returncode, timeout)
        with contextlib.suppress(OSError), socket.create_connection((host, port), timeout=0.5):
            return
        time.sleep(0.2)
    raise ProcessStartError(what, host, port, None, timeout)


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


def wait_children(procs: Sequence[subprocess.Popen[Any]], interval: float = 0.5) -> int:
    """Block until one child exits; report it on stderr and return 0 if it exited cleanly, else 1."""
    while True:
        for proc in procs:
            code = proc.poll()
            if code is not None:
                args = proc.args
                shown = args[3] if isinstance(args, list | tuple) and len(args) > 3 else args
                print(f"pmk: {shown!s} exited ({code})", file=sys.stderr)
                return 1 if code else 0
        time.sleep(interval)


@contextlib.contextmanager
def sigterm_as_interrupt() -> Iterator[None]:
    """Turn SIGTERM into KeyboardInterrupt so `finally` blocks stop the children."""

    def handler(_signum: int, _frame: object) -> None:
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGTERM, handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)
