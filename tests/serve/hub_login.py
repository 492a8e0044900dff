"""A student's way into a real ``pmk hub``, for the hub tests that run one (realtime: a real JupyterHub
logs in and spawns, so :func:`open_dashboard` polls it on the wall clock, bounded)."""

from __future__ import annotations

import re
import time
from typing import Any

import requests

from pmk_nb.serve.hub_config import DASHBOARD_URL

PASSWORD = "class-password-26"


def login(base: str, user: str, password: str) -> tuple[requests.Session, requests.Response]:
    """The hub's login form as a browser fills it: its xsrf cookie and hidden field, then the POST."""
    session = requests.Session()
    page = session.get(f"{base}/hub/login", timeout=30)
    field = re.search(r'name="_xsrf"[^>]*value="([^"]+)"', page.text)
    assert page.status_code == 200 and field, page.text[:500]
    form = {"username": user, "password": password, "_xsrf": field.group(1)}
    return session, session.post(f"{base}/hub/login", data=form, timeout=60)


def open_dashboard(base: str, user: str, results: dict[str, Any]) -> None:
    """Log in and open the dashboard (the spawn may take a while: poll, bounded)."""
    session, answer = login(base, user, PASSWORD)
    results[f"{user}-login"] = answer.status_code
    deadline = time.monotonic() + 90
    while time.monotonic() < deadline:
        page = session.get(f"{base}/user/{user}{DASHBOARD_URL}", timeout=90)
        if page.status_code == 200 and f"/user/{user}/voila/" in page.url:
            results[user] = page.text
            return
        time.sleep(1.0)
