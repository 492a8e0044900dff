"""Issue 24 from the command line: `pmk sim --tls` serves wss with a printed fingerprint; `pmk chair
test` without a terminal refuses an unknown certificate (never trusts silently), pins it with
--trust-fingerprint when it matches, and refuses a wrong one. Real processes, like a script runs them."""

from __future__ import annotations

import os
import re
import select
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from pmk_nb.chair import ProfileStore
from pmk_nb.chair.link.transport.tls import pinned
from tests.cli.test_sim_cli import start_cli

ROOT = Path(__file__).resolve().parents[2]


def _pmk(cfg: Path, *args: str) -> subprocess.CompletedProcess[str]:
    """`pmk ARGS` with stdin not a terminal (a script, a kiosk's service)."""
    env = {**os.environ, "PMK_CONFIG_DIR": str(cfg)}
    return subprocess.run(
        [sys.executable, "-m", "pmk_nb.cli", *args],
        stdin=subprocess.DEVNULL,
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
        cwd=ROOT,
    )


def _pmk_on_a_terminal(cfg: Path, answer: str, *args: str) -> tuple[int, str]:
    """`pmk ARGS` on a pseudo-terminal (a person at a shell): ``answer`` is typed at the question."""
    main, sub = os.openpty()
    env = {**os.environ, "PMK_CONFIG_DIR": str(cfg)}
    proc = subprocess.Popen(
        [sys.executable, "-m", "pmk_nb.cli", *args], stdin=sub, stdout=sub, stderr=sub, env=env, cwd=ROOT
    )
    os.close(sub)
    seen = b""
    deadline = time.monotonic() + 60
    try:
        while b"[y/N]" not in seen and time.monotonic() < deadline:
            ready, _, _ = select.select([main], [], [], 1.0)
            if ready:
                seen += os.read(main, 4096)
        assert b"[y/N]" in seen, seen.decode(errors="replace")
        os.write(main, answer.encode() + b"\n")
        while time.monotonic() < deadline:
            ready, _, _ = select.select([main], [], [], 1.0)
            try:
                chunk = os.read(main, 4096) if ready else b""
            except OSError:  # the child closed the terminal
                break
            if ready and not chunk:
                break
            seen += chunk
            if proc.poll() is not None and not ready:
                break
        return proc.wait(30), seen.decode(errors="replace")
    finally:
        os.close(main)
        if proc.poll() is None:
            proc.kill()


@pytest.mark.slow
def test_chair_test_over_wss_refuses_then_pins_the_given_fingerprint(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("PMK_CONFIG_DIR", str(tmp_path / "cfg"))  # this process reads what `pmk` wrote
    proc, lines = start_cli("--tls", "--no-sftp")
    try:
        text = "\n".join(lines)
        url = re.search(r"wss://127\.0\.0\.1:(\d+)", text)
        shown = re.search(r"tls certificate: SHA-256 ((?:[0-9A-F]{2}:){31}[0-9A-F]{2})", text)
        assert url and shown, text
        port, fingerprint = int(url.group(1)), shown.group(1)
        cfg = tmp_path / "cfg"
        added = _pmk(cfg, "chair", "add", "simtls", "--host", "127.0.0.1", "--port", str(port), "--tls")
        assert added.returncode == 0, added.stderr
        listed = _pmk(cfg, "chair", "list")
        assert f"wss://127.0.0.1:{port}" in listed.stdout

        refused = _pmk(cfg, "chair", "test", "--no-ssh")  # no tty: first contact refused
        assert refused.returncode == 1, refused.stdout + refused.stderr
        assert fingerprint in refused.stdout and "FAILED" in refused.stdout
        tls = ProfileStore(cfg / "profiles.json", secrets=False).get("simtls").link_options()["tls"]
        assert not tls.known_certs.exists()

        code, said = _pmk_on_a_terminal(cfg, "n", "chair", "test", "--no-ssh")  # a person says no
        assert code == 1 and fingerprint in said and not tls.known_certs.exists(), said

        wrong = "00" + fingerprint[2:] if not fingerprint.startswith("00") else "11" + fingerprint[2:]
        mismatch = _pmk(cfg, "chair", "test", "--no-ssh", "--trust-fingerprint", wrong)
        assert mismatch.returncode == 1 and not tls.known_certs.exists(), mismatch.stdout

        given = fingerprint.replace(":", "").lower()  # as pasted from openssl without colons
        ok = _pmk(cfg, "chair", "test", "--no-ssh", "--trust-fingerprint", given)
        assert ok.returncode == 0, ok.stdout + ok.stderr
        assert f"rosbridge wss://127.0.0.1:{port}: ok" in ok.stdout
        assert pinned(tls, "127.0.0.1", port) == fingerprint
    finally:
        proc.send_signal(signal.SIGTERM)
        proc.wait(20)


def test_sim_tls_options_are_checked(tmp_path: Path) -> None:
    env = {**os.environ, "PMK_CONFIG_DIR": str(tmp_path)}
    half = subprocess.run(
        [sys.executable, "-m", "pmk_nb.cli", "sim", "--port", "0", "--no-sftp", "--certfile", str(tmp_path / "c")],
        capture_output=True,
        text=True,
        env=env,
        timeout=60,
        cwd=ROOT,
    )
    assert half.returncode != 0 and "--keyfile" in half.stdout + half.stderr
