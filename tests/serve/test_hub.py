"""``pmk hub`` (issue 26): the generated JupyterHub configuration, the checks before anything starts,
and the helpers of the end-to-end test (:mod:`tests.browser.test_browser_hub`): ``pmk hub`` running on
loopback, a student logging in through the hub's own form (xsrf cookie and field) over HTTP.
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import stat
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import psutil
import pytest

from pmk_nb.serve import serving
from pmk_nb.serve.hub_config import (
    COOKIE_SECRET,
    DASHBOARD_URL,
    HubPlan,
    check_password,
    find_proxy,
    hub_config,
    parse_users,
    prepare_home,
    write_hub_config,
)
from pmk_nb.serve.procs import free_port
from tests.serve.hub_login import PASSWORD

REPO = Path(__file__).resolve().parents[2]


def _plan(tmp_path: Path, **kw: Any) -> HubPlan:
    values: dict[str, Any] = dict(
        users=("ana", "ben"),
        password=PASSWORD,
        ip="127.0.0.1",
        port=8000,
        hub_port=8081,
        proxy_api_port=8001,
        state_dir=tmp_path / "hub",
        users_dir=tmp_path / "users",
        maps_dir=tmp_path / "maps",
        classroom_file=tmp_path / "classroom" / "classroom.json",
        proxy_command=("/bin/chp",),
    )
    values.update(kw)
    return HubPlan(**values)


def test_the_config_uses_jupyterhubs_own_parts(tmp_path: Path) -> None:
    config = hub_config(_plan(tmp_path))
    hub = config["JupyterHub"]
    assert hub["authenticator_class"] == "jupyterhub.authenticators.shared.SharedPasswordAuthenticator"
    assert config["SharedPasswordAuthenticator"] == {"user_password": PASSWORD}
    assert config["Authenticator"] == {"allowed_users": ["ana", "ben"]}
    assert (hub["ip"], hub["port"], hub["hub_ip"]) == ("127.0.0.1", 8000, "127.0.0.1")
    assert hub["spawner_class"] == "pmk_nb.serve.hub_spawner.ClassSpawner"
    assert config["Spawner"]["default_url"] == DASHBOARD_URL
    assert config["Spawner"]["environment"]["PMK_CLASSROOM"] == str(tmp_path / "classroom" / "classroom.json")
    assert config["SimpleLocalProcessSpawner"]["home_dir_template"] == str(tmp_path / "users" / "{username}")
    assert config["ConfigurableHTTPProxy"] == {"command": ["/bin/chp"], "api_url": "http://127.0.0.1:8001"}
    (culler,) = hub["services"]
    assert culler["command"][1:] == ["-m", "jupyterhub_idle_culler", "--timeout=3600"]
    assert hub["load_roles"][0]["services"] == ["idle-culler"] and "delete:servers" in hub["load_roles"][0]["scopes"]
    assert "ssl_cert" not in hub and hub["cleanup_servers"] is True


def test_the_config_and_cookie_secret_are_private(tmp_path: Path) -> None:
    from pmk_nb.serve.tablet_tls import TlsFiles

    tls = TlsFiles(tmp_path / "c.pem", tmp_path / "k.pem", "AA", ("x",))
    path = write_hub_config(_plan(tmp_path, tls=tls))
    assert stat.S_IMODE(path.stat().st_mode) == 0o600  # it holds the class password
    assert stat.S_IMODE((path.parent / COOKIE_SECRET).stat().st_mode) == 0o600
    assert len((path.parent / COOKIE_SECRET).read_text().strip()) == 64
    hub = json.loads(path.read_text())["JupyterHub"]
    assert (hub["ssl_cert"], hub["ssl_key"]) == (str(tmp_path / "c.pem"), str(tmp_path / "k.pem"))


def test_users_and_password_are_checked_before_anything_starts() -> None:
    assert parse_users(" ana, ben ,chloe.d ") == ("ana", "ben", "chloe.d")
    for bad, reason in [("", "bad-users"), ("ana,Ben", "bad-users"), ("ana,ana", "bad-users")]:
        with pytest.raises(serving.ServingRefused) as err:
            parse_users(bad)
        assert err.value.reason == reason
    assert check_password("12345678", "127.0.0.1") == "12345678"
    with pytest.raises(serving.ServingRefused) as err:
        check_password("1234567", "127.0.0.1")
    assert err.value.reason == "weak-password"
    with pytest.raises(serving.ServingRefused) as err:
        check_password("12345678", "0.0.0.0")  # beyond loopback: a token's length, as pmk dashboard
    assert err.value.reason == "weak-password"
    with pytest.raises(serving.ServingRefused) as err:
        check_password(None, "127.0.0.1")
    assert err.value.reason == "no-password"
    with pytest.raises(serving.ServingRefused) as err:
        find_proxy("/nonexistent/configurable-http-proxy")
    assert err.value.reason == "no-proxy"


def test_a_students_home_gets_the_dashboard_and_keeps_their_edits(tmp_path: Path) -> None:
    home = tmp_path / "ana"
    prepare_home(home)
    assert "build_app()" in json.loads((home / "dashboard.ipynb").read_text())["cells"][0]["source"]
    tutorials = sorted(p.name for p in home.glob("0*.ipynb"))
    assert tutorials and tutorials[0].startswith("01-")
    (home / tutorials[0]).write_text("edited")
    prepare_home(home)
    assert (home / tutorials[0]).read_text() == "edited"


def test_pmk_hub_refuses_plain_http_beyond_loopback(tmp_path: Path) -> None:
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "pmk_nb.cli",
            "hub",
            "--users",
            "ana",
            "--password",
            "x" * 20,
            "--ip",
            "0.0.0.0",
            "--hub-dir",
            str(tmp_path),
            "--no-browser",
            "--port",
            str(free_port()),
        ],
        capture_output=True,
        text=True,
        timeout=60,
        cwd=REPO,
        env=_env(),
    )
    assert run.returncode != 0 and "--insecure" in run.stderr, run.stderr
    assert not (tmp_path / "hub").exists()  # refused before anything was made


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(REPO) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def _class_processes(hub: subprocess.Popen[Any]) -> list[psutil.Process]:
    return psutil.Process(hub.pid).children(recursive=True)


@contextlib.contextmanager
def running_hub(
    tmp_path: Path, users: str = "ana,ben", extra: tuple[str, ...] = ("--shared-user",)
) -> Iterator[tuple[str, subprocess.Popen[str], list[str]]]:
    """``pmk hub`` on a free loopback port until its URL is printed; SIGINT at the end (its exit code checked
    by the caller through the process).  Yields (base URL, the process, its output lines). ``extra``: more
    options (default ``--shared-user``: one user, as the browser test needs no system users)."""
    port = free_port()
    hub = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "pmk_nb.cli",
            "hub",
            "--users",
            users,
            "--password",
            PASSWORD,
            "--hub-dir",
            str(tmp_path),
            "--no-browser",
            "--port",
            str(port),
            *extra,
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        cwd=REPO,
        env=_env(),
    )
    seen: list[str] = []
    try:
        assert hub.stdout is not None
        for line in hub.stdout:
            seen.append(line)
            if line.startswith("PMK class hub:"):
                break
        assert any(f"127.0.0.1:{port}" in s for s in seen), "".join(seen)
        threading.Thread(target=lambda: seen.extend(hub.stdout or []), daemon=True).start()
        yield f"http://127.0.0.1:{port}", hub, seen
    finally:
        if hub.poll() is None:
            hub.send_signal(signal.SIGINT)
        try:
            hub.wait(timeout=60)
        except subprocess.TimeoutExpired:
            hub.kill()
            hub.wait()


def test_without_root_the_hub_refuses_unless_the_class_accepts_a_shared_user(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from pmk_nb.serve.hub_users import choose_isolation

    monkeypatch.setattr(os, "geteuid", lambda: 1000)
    with pytest.raises(serving.ServingRefused) as err:
        choose_isolation(False, None, tmp_path / "class1", ("ana",))
    assert err.value.reason == "no-isolation"
    assert not choose_isolation(True, None, tmp_path, ("ana",)).isolated
    monkeypatch.setattr(os, "geteuid", lambda: 0)
    isolation = choose_isolation(False, None, tmp_path / "Class-1", ("ana",))
    assert isolation.system_user("ana") == "pmk-class1-ana"
    with pytest.raises(serving.ServingRefused) as err:
        choose_isolation(False, "p" * 30 + "-", tmp_path, ("ana",))
    assert err.value.reason == "bad-users"


def test_the_spawner_is_told_the_students_users_and_their_files(tmp_path: Path) -> None:
    from pmk_nb.classroom.settings import StudentFiles, shared_user
    from pmk_nb.serve.hub_config import hub_environment
    from pmk_nb.serve.hub_users import USER_PREFIX_ENV, Isolation, prepare_student, student_env

    assert hub_environment(_plan(tmp_path, user_prefix="pmk-c-"), {"A": "1"}) == {"A": "1", USER_PREFIX_ENV: "pmk-c-"}
    home = tmp_path / "users" / "ana"
    prepare_student(home, None, None)
    files = StudentFiles.from_env(student_env(home, Isolation("pmk-c-")))
    assert files.secret_file is not None and files.private_key is not None
    assert stat.S_IMODE(files.secret_file.stat().st_mode) == 0o600 and len(files.secret_file.read_text().strip()) == 64
    assert stat.S_IMODE(files.private_key.stat().st_mode) == 0o600
    assert files.pages_dir is not None and files.pages_dir.parent == files.secret_file.parent
    assert not shared_user(student_env(home, Isolation("pmk-c-")))
    assert shared_user(student_env(home, Isolation()))
