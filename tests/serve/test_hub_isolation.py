"""``pmk hub`` keeps students apart (issue 38, item 2): a system user each, their own chair's secret.

The real hub as root (as on a lab server): Ana and Ben log in through the hub's form and open their
dashboards, which start their chairs. Code run as Ben's kernel's user (the uid his kernel runs under,
checked) cannot read Ana's home nor the hub's cookie secret, database or configuration (permission
denied), and cannot drive Ana's chair: without her secret the chair closes the socket, and with Ben's own
secret the link's authentication is refused. With Ana's secret (read here as root) the chair answers, so
the refusals are the chair's doing. When the hub stops, the users it made are gone.
"""

from __future__ import annotations

import contextlib
import json
import os
import pwd
import secrets
import shutil
import stat
import subprocess
import sys
import tempfile
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import psutil
import pytest

from pmk_nb.serve.hub_users import KEY_NAME, SECRET_FILE, STUDENT_DIR
from tests.serve.hub_login import open_dashboard
from tests.serve.test_hub import REPO, _class_processes, running_hub

pytestmark = [pytest.mark.slow, pytest.mark.timeout(400)]

# Run as Ben's user: try to read each path and to drive Ana's chair; print what happened as JSON.
PROBE = r"""
import json, sys, time
from pathlib import Path
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import connect
from pmk_nb.chair.link import ChairLink
from pmk_nb.chair.link.transport.bridge_auth import BridgeAuth, BridgeAuthError

args = json.loads(sys.argv[1])
out = {"uid": __import__("os").getuid(), "reads": {}}
for path in args["paths"]:
    try:
        Path(path).read_bytes()
        out["reads"][path] = "read"
    except PermissionError:
        out["reads"][path] = "denied"
    except OSError as err:
        out["reads"][path] = type(err).__name__
try:
    with connect(f"ws://127.0.0.1:{args['port']}", open_timeout=5) as ws:
        ws.send(json.dumps({"op": "advertise", "topic": "/cmd_vel", "type": "geometry_msgs/Twist"}))
        turn = {"linear": {"x": 0.5}, "angular": {"z": 1.0}}
        ws.send(json.dumps({"op": "publish", "topic": "/cmd_vel", "msg": turn}))
        ws.recv(timeout=10)
    out["no_auth"] = "served"
except ConnectionClosed as err:
    out["no_auth"] = f"closed {err.rcvd.code if err.rcvd else None}"
except TimeoutError:
    out["no_auth"] = "silent"
link = ChairLink("127.0.0.1", args["port"], auth=BridgeAuth(Path(args["own_secret"])))
try:
    link.connect(timeout=10)
    out["own_secret"] = "connected"
except BridgeAuthError as err:
    out["own_secret"] = "refused" if err.refused else "unreadable"
finally:
    link.close()
print(json.dumps(out))
"""


def _as_user(name: str, args: dict[str, Any]) -> dict[str, Any]:
    user = pwd.getpwnam(name)
    env = {"PATH": os.environ.get("PATH", ""), "PYTHONPATH": str(REPO), "HOME": user.pw_dir}
    run = subprocess.run(
        [sys.executable, "-c", PROBE, json.dumps(args)],
        user=user.pw_uid,
        group=user.pw_gid,
        extra_groups=[],
        env=env,
        cwd="/",
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 0, run.stderr[-2000:]
    return dict(json.loads(run.stdout.strip().splitlines()[-1]))


@contextlib.contextmanager
def _interpreter_reachable() -> Iterator[None]:
    """Other users may traverse (x only, no listing) the folders above this Python while the test runs: on
    this machine it lives under root's 0700 home, which a student's user cannot enter (pmk hub refuses then,
    reason "students-cannot-run"; a lab server installs Python where every user can run it). Restored after."""
    closed = [p for p in Path(os.path.realpath(sys.executable)).parents if not p.stat().st_mode & stat.S_IXOTH]
    modes = {p: stat.S_IMODE(p.stat().st_mode) for p in closed}
    try:
        for path, mode in modes.items():
            path.chmod(mode | stat.S_IXOTH)
        yield
    finally:
        for path, mode in modes.items():
            path.chmod(mode)


def _chair_answers(port: int, secret_file: Path) -> bool:
    from pmk_nb.chair.link import ChairLink
    from pmk_nb.chair.link.transport.bridge_auth import BridgeAuth

    link = ChairLink("127.0.0.1", port, auth=BridgeAuth(secret_file))
    try:
        link.connect(timeout=10)
        return link.is_connected
    finally:
        link.close()


def test_students_cannot_read_each_other_nor_drive_each_others_chair() -> None:
    if os.geteuid() != 0:
        pytest.fail("this test needs root: pmk hub gives each student a system user only as root")
    root = Path(tempfile.mkdtemp(prefix="pmkt-hub-", dir="/tmp"))
    root.chmod(0o755)
    prefix = f"pmkt-{secrets.token_hex(2)}-"
    ana, ben = f"{prefix}ana", f"{prefix}ben"
    try:
        with _interpreter_reachable(), running_hub(root, extra=("--user-prefix", prefix)) as (base, hub, seen):
            results: dict[str, Any] = {}
            threads = [threading.Thread(target=open_dashboard, args=(base, u, results)) for u in ("ana", "ben")]
            for t in threads:
                t.start()
            for t in threads:
                t.join(timeout=200)
            assert "ana" in results and "ben" in results, f"dashboards did not open: {results.keys()} {''.join(seen)}"
            chairs = json.loads((root / "classroom" / "seats" / "chairs.json").read_text())
            by_user = {e["user"]: e for e in chairs.values()}
            assert set(by_user) == {"ana", "ben"}, chairs
            kernels = {p.username() for p in _class_processes(hub) if "ipykernel" in " ".join(p.cmdline())}
            assert {ana, ben} <= kernels, kernels  # each student's kernel runs as their own user
            ana_home, hub_dir = root / "users" / "ana", root / "hub"
            assert (ana_home.stat().st_mode & 0o777, ana_home.stat().st_uid) == (0o700, pwd.getpwnam(ana).pw_uid)
            ana_secret = ana_home / STUDENT_DIR / SECRET_FILE
            ben_secret = root / "users" / "ben" / STUDENT_DIR / SECRET_FILE
            private = [
                str(ana_secret),
                str(ana_home / STUDENT_DIR / KEY_NAME),
                str(ana_home / "dashboard.ipynb"),
                str(hub_dir / "jupyterhub_cookie_secret"),
                str(hub_dir / "jupyterhub.sqlite"),
                str(hub_dir / "jupyterhub_config.json"),
            ]
            out = _as_user(
                ben,
                {
                    "paths": [*private, str(ben_secret)],
                    "port": by_user["ana"]["ros_port"],
                    "own_secret": str(ben_secret),
                },
            )
            assert out["uid"] == pwd.getpwnam(ben).pw_uid
            assert {p: out["reads"][p] for p in private} == dict.fromkeys(private, "denied"), out
            assert out["reads"][str(ben_secret)] == "read"  # his own secret: the denials are not a broken probe
            assert out["no_auth"] == "closed 1008", out  # no auth op: refused, nothing published
            assert out["own_secret"] == "refused", out  # Ben's secret is not Ana's chair's
            assert _chair_answers(int(by_user["ana"]["ros_port"]), ana_secret)  # Ana's secret: served
        assert hub.returncode == 0, "".join(seen)
        for name in (ana, ben):
            with pytest.raises(KeyError):
                pwd.getpwnam(name)  # the hub removed the users it made
        assert not [p for p in psutil.process_iter(["username"]) if p.info["username"] in (ana, ben)]
    finally:
        for name in (ana, ben):
            subprocess.run(["userdel", name], check=False, capture_output=True)
        shutil.rmtree(root, ignore_errors=True)
