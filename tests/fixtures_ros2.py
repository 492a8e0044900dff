"""The real-stack tier: a real rosbridge server (rosbridge-server-rs) bridging the project's rclpy nodes.

- ``ros2_stack`` -> the Jazzy wheels stack `make ros2` set up (:mod:`pmk_nb.robot.wheels`). A test
  that needs it FAILS, naming the command to run, when it is missing: never a skip.
- ``real_chair`` -> a :class:`RealChair` on a private ``ROS_DOMAIN_ID`` with DDS kept on loopback
  (``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``): start the bridge, the map server and the sim node
  on it, kill and restart them; everything is stopped at teardown. The bridge runs with rosapi when
  asked (``rosapi_msgs`` is built by `make ros2`), without it by default.

Import the fixtures into a test module (``from tests.fixtures_ros2 import real_chair, ros2_stack``).
"""

from __future__ import annotations

import itertools
import os
import socket
import subprocess
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import pytest
import roslibpy

from pmk_nb.robot import wheels
from tests.fixtures_sim import ROSLIBPY_TRANSPORT

_domains = itertools.count()
BIG_BYTES = 1024**3  # the bridge estimates a big OccupancyGrid far above its JSON size


def private_domain() -> int:
    """A DDS domain no other test process on this machine uses at the same time (1..200)."""
    return 1 + (os.getpid() * 7 + next(_domains)) % 200


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@dataclass
class Proc:
    """One process of the stack, its output collected in a file (and its first lines watched)."""

    name: str
    popen: subprocess.Popen[bytes]
    log: Path
    ready: threading.Event = field(default_factory=threading.Event)

    def tail(self, chars: int = 2000) -> str:
        return self.log.read_text(errors="replace")[-chars:] if self.log.exists() else ""

    def stop(self) -> None:
        if self.popen.poll() is None:
            self.popen.terminate()
            try:
                self.popen.wait(5)
            except subprocess.TimeoutExpired:
                self.popen.kill()
                self.popen.wait(5)


def close_client(ros: roslibpy.Ros) -> None:
    """Close a roslibpy client for good (no background reconnects after the test)."""
    ros.factory._stop = True  # roslibpy has no API for it (as in fixtures_sim.ros_factory)
    try:
        if ros.is_connected:
            ros.close()
    except Exception:
        pass


class RealChair:
    """The chair side on loopback: rosbridge-server-rs + our rclpy nodes on one private domain."""

    def __init__(self, stack: wheels.Stack, tmp: Path) -> None:
        self.stack = stack
        self.tmp = tmp
        self.domain = private_domain()
        self.port = free_port()
        self.maps = tmp / "ALMA_MAPS"
        self.maps.mkdir(parents=True, exist_ok=True)
        self.procs: dict[str, Proc] = {}

    def _spawn(self, name: str, cmd: list[str], env: dict[str, str], ready_text: str | None) -> Proc:
        log = self.tmp / f"{name}.log"
        popen = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, cwd=self.tmp)
        proc = Proc(name, popen, log)

        def pump() -> None:  # the log file, and the ready line when it shows
            assert popen.stdout is not None
            with log.open("ab") as out:
                for line in popen.stdout:
                    out.write(line)
                    out.flush()
                    if ready_text and ready_text.encode() in line:
                        proc.ready.set()

        threading.Thread(target=pump, daemon=True, name=f"log-{name}").start()
        self.procs[name] = proc
        return proc

    def start_bridge(
        self, *, rosapi: bool = False, write_queue_bytes: int | None = None, timeout: float = 20, big: bool = False
    ) -> None:
        """rosbridge-server-rs on 127.0.0.1:port; returns once it accepts connections.

        ``rosapi`` needs rosapi_msgs (built by `make ros2`); ``big`` raises the send queue and the
        message size limit so that a 4000x4000 grid crosses as JSON (Nav2 chairs need this).
        """
        cmd = [str(self.stack.server), "--bind", f"127.0.0.1:{self.port}", "--log-ansi", "false"]
        cmd += [] if rosapi else ["--no-rosapi"]
        if big:
            write_queue_bytes = write_queue_bytes or BIG_BYTES
            cmd += ["--max-message-size", str(BIG_BYTES)]
        if write_queue_bytes:
            cmd += ["--write-queue-bytes", str(write_queue_bytes)]
        proc = self._spawn("bridge", cmd, self.stack.process_env(self.domain), None)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if proc.popen.poll() is not None:
                pytest.fail(f"rosbridge-server-rs exited ({proc.popen.returncode}):\n{proc.tail()}")
            try:
                socket.create_connection(("127.0.0.1", self.port), timeout=0.5).close()
                return
            except OSError:
                time.sleep(0.05)
        pytest.fail(f"rosbridge-server-rs did not listen on {self.port} within {timeout} s:\n{proc.tail()}")

    def start_node(self, name: str, args: list[str], ready_text: str, timeout: float = 30) -> Proc:
        """``pmk robot ARGS`` with the stack's python; returns once it printed ``ready_text``."""
        cmd = [str(self.stack.python), "-m", "pmk_nb.cli", "robot", *args]
        proc = self._spawn(name, cmd, self.stack.node_env(self.domain), ready_text)
        if not proc.ready.wait(timeout):
            pytest.fail(f"{name} did not get ready within {timeout} s (exit {proc.popen.poll()}):\n{proc.tail()}")
        return proc

    def start_map_server(self, map_name: str | None = None, *extra: str) -> Proc:
        from pmk_nb.robot.mapserver import READY_LINE

        args = ["map-server", "--maps", str(self.maps), *(["--map", map_name] if map_name else []), *extra]
        return self.start_node("map_server", args, READY_LINE)

    def start_sim_node(self, *extra: str) -> Proc:
        from pmk_nb.robot.simnode import READY_LINE

        return self.start_node("sim_node", ["sim-node", "--maps", str(self.maps), *extra], READY_LINE)

    def kill(self, name: str) -> None:
        self.procs.pop(name).stop()

    def client(self) -> roslibpy.Ros:
        """A bare roslibpy client of the bridge (the caller terminates it)."""
        ros = roslibpy.Ros("127.0.0.1", self.port, transport=ROSLIBPY_TRANSPORT)
        ros.run(timeout=10)
        return ros

    def wait_service(self, name: str, srv_type: str, request: dict | None = None, timeout: float = 20) -> dict:
        """Call ``name`` until the bridge sees it in the ROS graph (DDS discovery takes a moment)."""
        ros = self.client()
        try:
            deadline = time.monotonic() + timeout
            last: Exception | None = None
            while time.monotonic() < deadline:
                try:
                    svc = roslibpy.Service(ros, name, srv_type)
                    return dict(svc.call(roslibpy.ServiceRequest(request or {}), timeout=5))
                except Exception as err:  # discovery not done yet: the bridge says the type is unknown
                    last = err
                    time.sleep(0.2)
            tails = "\n".join(f"--- {p.name}:\n{p.tail(800)}" for p in self.procs.values())
            pytest.fail(f"{name} not reachable through the bridge within {timeout} s ({last}):\n{tails}")
        finally:
            close_client(ros)

    def stop(self) -> None:
        for proc in list(self.procs.values()):
            proc.stop()
        self.procs.clear()


@pytest.fixture(scope="session")
def ros2_stack() -> wheels.Stack:
    try:
        return wheels.load()
    except wheels.StackMissing as err:
        pytest.fail(f"real-stack tier: {err}", pytrace=False)


@pytest.fixture
def real_chair(ros2_stack: wheels.Stack, tmp_path: Path) -> Iterator[RealChair]:
    chair = RealChair(ros2_stack, tmp_path)
    try:
        yield chair
    finally:
        chair.stop()
