"""The CLI's child-process helpers: waiting for a port, typed start errors, no child left behind."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
from pathlib import Path

import pytest

from pmk_nb.errors import PmkError
from pmk_nb.serve.procs import ProcessStartError, free_port, sigterm_as_interrupt, stop_process, wait_for_port


def test_wait_for_port_returns_once_the_child_listens() -> None:
    port = free_port()
    code = f"import socket,time; s=socket.socket(); s.bind(('127.0.0.1',{port})); s.listen(); time.sleep(30)"
    proc = subprocess.Popen([sys.executable, "-c", code])
    try:
        wait_for_port("127.0.0.1", port, proc, "listener", 20.0)
        with socket.create_connection(("127.0.0.1", port), timeout=2):
            pass
    finally:
        stop_process(proc, timeout=5.0)
    assert proc.returncode is not None  # stopped: no child left behind


def test_a_child_that_dies_is_a_typed_error_with_its_exit_code() -> None:
    port = free_port()
    proc = subprocess.Popen([sys.executable, "-c", "raise SystemExit(3)"])
    with pytest.raises(ProcessStartError) as caught:
        wait_for_port("127.0.0.1", port, proc, "the dying child", 20.0)
    err = caught.value
    assert isinstance(err, PmkError)
    assert (err.what, err.host, err.port, err.returncode) == ("the dying child", "127.0.0.1", port, 3)


@pytest.mark.slow
def test_a_child_that_never_listens_times_out() -> None:
    port = free_port()
    proc = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"])
    try:
        with pytest.raises(ProcessStartError) as caught:
            wait_for_port("127.0.0.1", port, proc, "the silent child", 0.6)
    finally:
        stop_process(proc, timeout=5.0)
    assert caught.value.returncode is None and caught.value.timeout == 0.6
    assert proc.poll() is not None


def test_sigterm_becomes_keyboard_interrupt_only_inside_the_block() -> None:
    before = signal.getsignal(signal.SIGTERM)
    with pytest.raises(KeyboardInterrupt), sigterm_as_interrupt():
        signal.raise_signal(signal.SIGTERM)
    assert signal.getsignal(signal.SIGTERM) == before


def test_a_reader_that_leaves_early_ends_pmk_quietly(tmp_path: Path) -> None:
    """`pmk check --json FILE | head`: the pipe closes before pmk writes; no traceback, SIGPIPE's status."""
    from pmk_nb.cli import BROKEN_PIPE

    sample = Path(__file__).resolve().parents[2] / "sample_maps" / "clinic_floor.gml"
    env = dict(os.environ, PMK_CONFIG_DIR=str(tmp_path))
    proc = subprocess.Popen(
        [sys.executable, "-m", "pmk_nb.cli", "check", str(sample), "--json"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        env=env,
    )
    assert proc.stdout is not None
    proc.stdout.close()  # the reader is gone before the first byte
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == BROKEN_PIPE, err.decode()
    assert b"Traceback" not in err


@pytest.mark.slow
def test_the_demo_simulator_starts_again_on_other_ports_when_one_was_taken_meanwhile(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``pmk demo`` picks two free ports and starts ``pmk sim`` on them; another program may bind one
    first (a make test run saw it). The simulator says so by its exit status and starts again on
    other ports; any other failure still raises at once."""
    from pmk_nb.cli import demo_setup

    taken = socket.socket()
    taken.bind(("127.0.0.1", 0))
    taken.listen()
    port = taken.getsockname()[1]
    handed = iter([free_port(), port])  # the first start gets the taken port for its SFTP server
    monkeypatch.setattr(demo_setup, "free_port", lambda: next(handed, None) or free_port())
    starts: list[tuple[int, int]] = []
    map_arg: list[str] = []

    def command(ros: int, sftp: int) -> list[str]:
        starts.append((ros, sftp))
        return [sys.executable, "-m", "pmk_nb.cli", "sim", "--port", str(ros), "--sftp-port", str(sftp), *map_arg]

    with (tmp_path / "sim.log").open("ab") as log:
        try:
            sim, ros, sftp = demo_setup._start_sim(sim_command_for=command, env=dict(os.environ), log=log, cwd=tmp_path)
        finally:
            taken.close()
        try:
            assert sim.poll() is None, "the second start runs"
            assert len(starts) == 2 and starts[0][1] == port and port not in (ros, sftp)
        finally:
            stop_process(sim)

    starts.clear()
    map_arg[:] = ["--map", str(tmp_path / "missing.yaml")]  # not a port: no second start, the error at once
    with (tmp_path / "bad.log").open("ab") as log, pytest.raises(ProcessStartError):
        demo_setup._start_sim(sim_command_for=command, env=dict(os.environ), log=log, cwd=tmp_path)
    assert len(starts) == 1
