"""What a served dashboard leaves running, measured from outside: kernels, chair connections, memory.

Shared by the page-lifecycle browser tests and the soak (``bench/soak.py``).  Everything is read
from the operating system (psutil), never from the processes' own bookkeeping.
"""

from __future__ import annotations

import contextlib
import socket
import threading
import time
from collections.abc import Callable

import psutil


def voila_process(port: int) -> psutil.Process:
    """The Voilà server listening on ``port`` (a child of this process)."""
    for proc in psutil.Process().children(recursive=True):
        with contextlib.suppress(psutil.Error):
            cmd = " ".join(proc.cmdline())
            if "voila" in cmd and f"--port={port}" in cmd:
                return proc
    raise AssertionError(f"no Voilà process serving port {port}")


def kernels(voila: psutil.Process) -> list[psutil.Process]:
    """Live (not zombie) kernel processes under ``voila``."""
    found = []
    for proc in voila.children(recursive=True):
        with contextlib.suppress(psutil.Error):
            if proc.status() != psutil.STATUS_ZOMBIE and "ipykernel" in " ".join(proc.cmdline()):
                found.append(proc)
    return found


def chair_connections(sim_pid: int, ros_port: int) -> int:
    """Established TCP connections to the simulated chair's rosbridge port (one per page link)."""
    conns = psutil.Process(sim_pid).net_connections("tcp")
    return sum(1 for c in conns if c.status == psutil.CONN_ESTABLISHED and c.laddr.port == ros_port)


def rss_mb(proc: psutil.Process) -> float:
    return proc.memory_info().rss / 2**20


def open_fds(proc: psutil.Process) -> int:
    return proc.num_fds()


def wait_until(condition: Callable[[], bool], timeout: float, interval: float = 0.5) -> float | None:
    """Seconds until ``condition()`` held, or None if it never did within ``timeout``."""
    start = time.monotonic()
    while time.monotonic() - start < timeout:
        if condition():
            return time.monotonic() - start
        time.sleep(interval)
    return None


class FreezableProxy:
    """A TCP proxy to ``port`` that can stop forwarding without closing anything.

    ``freeze()`` is a tablet that went to sleep or lost its Wi-Fi: the connections stay open,
    nothing passes (no FIN, no RST), exactly the half-open websocket a server cannot tell from a
    quiet one.  ``thaw()`` lets data through again (and so the closes that happened meanwhile).
    """

    def __init__(self, port: int) -> None:
        self.target = port
        self._flowing = threading.Event()
        self._flowing.set()
        self._stop = threading.Event()
        self._listener = socket.create_server(("127.0.0.1", 0))
        self.port = int(self._listener.getsockname()[1])
        self._sockets: list[socket.socket] = []
        threading.Thread(target=self._accept, daemon=True).start()

    def freeze(self) -> None:
        self._flowing.clear()

    def thaw(self) -> None:
        self._flowing.set()

    def close(self) -> None:
        self._stop.set()
        self._flowing.set()
        for sock in [self._listener, *self._sockets]:
            with contextlib.suppress(OSError):
                sock.close()

    def _accept(self) -> None:
        while not self._stop.is_set():
            try:
                client, _ = self._listener.accept()
                upstream = socket.create_connection(("127.0.0.1", self.target))
            except OSError:
                return
            self._sockets += [client, upstream]
            for src, dst in ((client, upstream), (upstream, client)):
                threading.Thread(target=self._pump, args=(src, dst), daemon=True).start()

    def _pump(self, src: socket.socket, dst: socket.socket) -> None:
        try:
            while not self._stop.is_set():
                self._flowing.wait()
                data = src.recv(65536)
                if not data:
                    break
                while not self._flowing.is_set():  # frozen after the read: hold the bytes
                    self._flowing.wait(0.5)
                dst.sendall(data)
        except OSError:
            pass
        finally:
            for sock in (src, dst):
                with contextlib.suppress(OSError):
                    sock.shutdown(socket.SHUT_RDWR)
