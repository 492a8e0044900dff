"""The kiosk page every browser test opens: Voilà serving the dashboard, headless Chromium at it.

Moved verbatim out of ``test_browser_kiosk`` so the browser tests (and ``bench/classroom_pages.py``) share it
without importing another test module.
"""

from __future__ import annotations

import contextlib
import shutil
import subprocess
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.cli.demo_setup import DemoWorld, prepare_demo
from pmk_nb.serve.procs import free_port, stop_process, wait_for_port
from pmk_nb.serve.voila import voila_command, write_dashboard_notebook

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--headless",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
ARTIFACTS = Path(__file__).resolve().parents[2] / "test-artifacts"
VIEWPORT = {"width": 1280, "height": 800}  # a landscape tablet
SMALL_VIEWPORT = {"width": 1024, "height": 768}  # an older one


@contextlib.contextmanager
def serve_kiosk(
    tmp_path: Path, sim_args: Sequence[str] = (), label: str = "kiosk", env: dict[str, str] | None = None
) -> Iterator[tuple[str, DemoWorld]]:
    """The demo world (simulated chair, converted sample, profile) and Voilà serving the dashboard.

    ``env`` adds to the server's environment (e.g. ``PMK_KIOSK=1`` for kiosk mode).
    """
    world = prepare_demo(tmp_path / "demo", sim_args=sim_args)
    world.env.update(env or {})
    port = free_port()
    notebook = write_dashboard_notebook(tmp_path / "kiosk")
    log = (tmp_path / "voila.log").open("wb")
    voila = subprocess.Popen(
        voila_command(notebook, port=port), env=world.env, cwd=notebook.parent, stdout=log, stderr=subprocess.STDOUT
    )
    try:
        wait_for_port("127.0.0.1", port, voila, "Voilà", 120.0)
        yield f"http://127.0.0.1:{port}/", world
    finally:
        stop_process(voila)
        world.stop()
        log.close()
        ARTIFACTS.mkdir(exist_ok=True)
        shutil.copy(tmp_path / "voila.log", ARTIFACTS / f"{label}-voila.log")
        if world.log_path and world.log_path.exists():
            shutil.copy(world.log_path, ARTIFACTS / f"{label}-sim.log")


@contextlib.contextmanager
def chromium_page(url: str, **page_options: Any) -> Iterator[Any]:
    """A Playwright page in Debian's Chromium at ``url``; fails (never skips) without Chromium."""
    if not CHROMIUM.exists():
        pytest.fail(f"{CHROMIUM} is missing: install Debian's chromium package (apt-get install -y chromium)")
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS, headless=True)
        try:
            page = browser.new_page(**page_options)
            page.set_default_timeout(60_000)
            page.goto(url, wait_until="domcontentloaded")
            yield page
        finally:
            browser.close()
