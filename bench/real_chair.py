"""The real chair side for benchmarks: rosbridge-server-rs bridging the project's rclpy sim node.

Uses the Jazzy wheels stack `make ros2` set up (:mod:`pmk_nb.robot.wheels`), DDS on loopback and a
private domain, everything on 127.0.0.1; both processes are stopped when the block ends.
"""

from __future__ import annotations

import contextlib
import os
import socket
import subprocess
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

from pmk_nb.robot import wheels
from pmk_nb.robot.simnode import READY_LINE


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _stop(proc: subprocess.Popen[bytes]) -> None:
    if proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(5)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait(5)


def _wait_port(port: int, proc: subprocess.Popen[bytes], log: Path, timeout: float = 20.0) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            raise RuntimeError(f"rosbridge-server-rs exited:\n{log.read_text(errors='replace')[-2000:]}")
        try:
            socket.create_connection(("127.0.0.1", port), timeout=0.5).close()
            return
        except OSError:
            time.sleep(0.05)
    raise RuntimeError(f"rosbridge-server-rs did not listen on {port}")


def _wait_line(log: Path, text: str, proc: subprocess.Popen[bytes], timeout: float = 30.0) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if text in log.read_text(errors="replace"):
            return
        if proc.poll() is not None:
            break
        time.sleep(0.1)
    raise RuntimeError(f"the sim node did not start:\n{log.read_text(errors='replace')[-2000:]}")


@contextlib.contextmanager
def real_sim_chair(sim_args: list[str]) -> Iterator[int]:
    """Start the bridge (no rosapi) and ``pmk robot sim-node SIM_ARGS``; yields the bridge's port."""
    stack = wheels.load()
    domain = 1 + (os.getpid() * 7) % 200
    port = _free_port()
    procs: list[subprocess.Popen[bytes]] = []
    with tempfile.TemporaryDirectory(prefix="pmk-bench-") as tmp:
        logs = Path(tmp)
        try:
            cmd = [str(stack.server), "--bind", f"127.0.0.1:{port}", "--log-ansi", "false", "--no-rosapi"]
            with (logs / "bridge.log").open("wb") as out:
                procs.append(subprocess.Popen(cmd, env=stack.process_env(domain), stdout=out, stderr=out))
            _wait_port(port, procs[-1], logs / "bridge.log")
            node = [str(stack.python), "-m", "pmk_nb.cli", "robot", "sim-node", "--maps", tmp, *sim_args]
            with (logs / "sim.log").open("wb") as out:
                procs.append(subprocess.Popen(node, env=stack.node_env(domain), stdout=out, stderr=out))
            _wait_line(logs / "sim.log", READY_LINE, procs[-1])
            yield port
        finally:
            for proc in reversed(procs):
                _stop(proc)
