"""``pmk hub`` end to end (issue 26): two students, each their own server and chair; Ctrl-C ends all.

The real JupyterHub, its real proxy (configurable-http-proxy) and real single-user servers rendering
the dashboard with Voilà's server extension, on loopback.  Ana logs in through the login form in
Chromium and her dashboard reaches Live (its kernel websocket goes through the proxy); at the same
time Ben logs in over HTTP (the form's xsrf cookie and field) and opens his.  Each gets a server and
a chair of their own (different ports); a wrong password gets 403 and the login form again; after
SIGINT no process of the class is left.  Screenshot: ``test-artifacts/hub-student.png``.
"""

from __future__ import annotations

import json
import socket
import threading
import time
from pathlib import Path
from typing import Any

import psutil
import pytest

from tests.browser.kiosk_page import ARTIFACTS, VIEWPORT, chromium_page
from tests.serve.hub_login import PASSWORD, login, open_dashboard
from tests.serve.test_hub import _class_processes, running_hub

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]


def _ana_in_chromium(base: str) -> None:
    from playwright.sync_api import expect

    with chromium_page(f"{base}/hub/login", viewport=VIEWPORT) as page:
        page.fill("#username_input", "ana")
        page.fill("#password_input", PASSWORD)
        page.click("#login_submit")
        expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=180_000)
        assert page.url.endswith("/user/ana/voila/render/dashboard.ipynb")
        # --shared-user: the page says the class has no isolation (tests/serve/test_hub_isolation.py: with it)
        expect(page.locator(".pmk-app")).to_contain_text("No isolation in this class")
        ARTIFACTS.mkdir(exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "hub-student.png"))


def test_two_students_get_their_own_server_and_chair_and_ctrl_c_ends_all(tmp_path: Path) -> None:
    with running_hub(tmp_path) as (base, hub, seen):
        _session, refused = login(base, "ben", "not-the-password")  # wrong: 403 and the form again
        assert refused.status_code == 403 and 'name="_xsrf"' in refused.text
        results: dict[str, Any] = {}
        ben = threading.Thread(target=open_dashboard, args=(base, "ben", results))
        ben.start()
        _ana_in_chromium(base)
        ben.join(timeout=120)
        assert results.get("ben-login") == 200 and "ben" in results, f"Ben's dashboard did not open: {results.keys()}"
        chairs = json.loads((tmp_path / "classroom" / "chairs.json").read_text())
        by_user = {e["user"]: e for e in chairs.values()}
        assert set(by_user) == {"ana", "ben"}, chairs  # each student's page started its own chair
        assert by_user["ana"]["ros_port"] != by_user["ben"]["ros_port"]
        for entry in by_user.values():
            socket.create_connection(("127.0.0.1", int(entry["ros_port"])), timeout=5).close()
        servers = [p for p in _class_processes(hub) if "jupyterhub.singleuser" in " ".join(p.cmdline())]
        assert len(servers) == 2 and (tmp_path / "users" / "ana" / "dashboard.ipynb").is_file()
        everything = _class_processes(hub)
        assert len(everything) >= 6  # proxy, culler, 2 servers, 2 kernels (+ the hub under pmk hub)
    assert hub.returncode == 0, "".join(seen)
    time.sleep(1.0)
    left = [p for p in everything if p.is_running() and p.status() != psutil.STATUS_ZOMBIE]
    assert not left, f"left behind after Ctrl-C: {[' '.join(p.cmdline())[:100] for p in left]}"
    with pytest.raises(OSError):
        socket.create_connection(("127.0.0.1", int(base.rsplit(":", 1)[1])), timeout=2).close()
