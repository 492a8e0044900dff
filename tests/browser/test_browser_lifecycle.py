"""Kernels end with their page, in Chromium against the simulated chair (issue 10, part 1).

Opening and closing 20 pages (closed with and without ``beforeunload``), reloading a page, and a
page whose connection goes silent (a sleeping tablet: :class:`FreezableProxy`) must return chair
connections (and, for closed pages, kernels and Voilà's memory) to where they were.  Counts are read from the
operating system (tests/page_probes.py).
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.cli.demo_setup import DemoWorld
from tests.browser.kiosk_page import CHROMIUM, CHROMIUM_ARGS, serve_kiosk
from tests.page_probes import (
    FreezableProxy,
    chair_connections,
    kernels,
    rss_mb,
    voila_process,
    wait_until,
)

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(600)]

VIEWPORT = {"width": 1280, "height": 800}
GONE_WITHIN = 30.0  # generous for a loaded test machine; the design target (10 s) is measured by make soak
RSS_TOLERANCE_MB = 20.0  # measured +9 MB; +33-44 MB before the reaper collected page garbage
ROUNDS, PAGES_PER_ROUND = 5, 4  # 20 pages, four at a time


@pytest.fixture
def served(tmp_path: Path) -> Iterator[tuple[str, DemoWorld, Any]]:
    with serve_kiosk(tmp_path, label="lifecycle") as (url, world):
        port = int(url.rstrip("/").rsplit(":", 1)[1])
        yield url, world, voila_process(port)


@pytest.fixture
def browser() -> Iterator[Any]:
    if not CHROMIUM.exists():
        pytest.fail(f"{CHROMIUM} is missing: install Debian's chromium package (apt-get install -y chromium)")
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        b = pw.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS, headless=True)
        try:
            yield b
        finally:
            b.close()


def _open_live(browser: Any, url: str) -> Any:
    """A new page (own context) showing Home with the live view running."""
    from playwright.sync_api import expect

    page = browser.new_context(viewport=VIEWPORT).new_page()
    page.set_default_timeout(120_000)
    page.goto(url, wait_until="domcontentloaded")
    expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
    return page


def _settled(world: DemoWorld, voila: Any, pages: int) -> bool:
    return len(kernels(voila)) == pages and chair_connections(world.sim.pid, world.ros_port) == pages


def test_twenty_pages_opened_and_closed_leave_nothing_behind(served: tuple[str, DemoWorld, Any], browser: Any) -> None:
    url, world, voila = served
    warm = _open_live(browser, url)  # Voilà loads its templates on the first page: measure after that
    warm.context.close()
    assert wait_until(lambda: _settled(world, voila, 0), GONE_WITHIN) is not None, "the warm-up page's kernel stayed"
    baseline = rss_mb(voila)
    times = []
    for n in range(ROUNDS):
        pages = [_open_live(browser, url) for _ in range(PAGES_PER_ROUND)]
        assert wait_until(lambda: _settled(world, voila, PAGES_PER_ROUND), 30.0) is not None, (
            f"round {n}: expected {PAGES_PER_ROUND} kernels and chair connections, "
            f"got {len(kernels(voila))} and {chair_connections(world.sim.pid, world.ros_port)}"
        )
        for i, page in enumerate(pages):  # half with beforeunload (Voilà's beacon), half without
            page.close(run_before_unload=bool(i % 2))
            page.context.close()
        took = wait_until(lambda: _settled(world, voila, 0), GONE_WITHIN)
        assert took is not None, (
            f"round {n}: {len(kernels(voila))} kernels and "
            f"{chair_connections(world.sim.pid, world.ros_port)} chair connections outlived their pages"
        )
        times.append(took)
    grown = rss_mb(voila) - baseline
    print(f"\npages gone after {max(times):.1f} s at most; Voilà RSS {baseline:.0f} MB -> {baseline + grown:.0f} MB")
    assert grown < RSS_TOLERANCE_MB, f"Voilà grew by {grown:.0f} MB over 20 closed pages"


def test_a_reloaded_page_keeps_one_kernel_and_one_chair_connection(
    served: tuple[str, DemoWorld, Any], browser: Any
) -> None:
    from playwright.sync_api import expect

    url, world, voila = served
    page = _open_live(browser, url)
    first = {p.pid for p in kernels(voila)}
    for _ in range(3):
        page.reload(wait_until="domcontentloaded")
        expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
    assert wait_until(lambda: _settled(world, voila, 1), GONE_WITHIN) is not None, (
        f"after 3 reloads: {len(kernels(voila))} kernels, {chair_connections(world.sim.pid, world.ros_port)} links"
    )
    assert {p.pid for p in kernels(voila)}.isdisjoint(first), "the first page's kernel survived the reloads"


def test_a_page_whose_connection_goes_silent_stops_its_live_view_and_chair_link(
    served: tuple[str, DemoWorld, Any], browser: Any
) -> None:
    """A tablet asleep: the websocket stays open but nothing passes; the kernel must fall quiet."""
    from playwright.sync_api import expect

    url, world, voila = served
    proxy = FreezableProxy(int(url.rstrip("/").rsplit(":", 1)[1]))
    try:
        page = _open_live(browser, f"http://127.0.0.1:{proxy.port}/")
        expect(page.locator(".pmk-page-pong")).not_to_have_text("0", timeout=60_000)  # the heartbeat runs
        assert len(kernels(voila)) == 1
        proxy.freeze()
        took = wait_until(lambda: chair_connections(world.sim.pid, world.ros_port) == 0, GONE_WITHIN)
        assert took is not None, "a page whose connection went silent kept its chair connection"
        print(f"\nsilent page: chair connection closed after {took:.1f} s")
        kernel = kernels(voila)[0]
        kernel.cpu_percent(interval=None)
        time.sleep(3.0)
        cpu = kernel.cpu_percent(interval=None)
        assert cpu < 5.0, f"the kernel of a silent page still works ({cpu:.0f} % CPU): the live view runs on"
    finally:
        proxy.close()


def _page_sockets(voila: Any, port: int) -> int:
    """Established connections to Voilà's port (the page's websocket among them)."""
    conns = voila.net_connections("tcp")
    return sum(1 for c in conns if c.status == "ESTABLISHED" and c.laddr.port == port)


def test_a_sleeping_tablet_ends_its_kernel_and_reloads_when_it_wakes(
    served: tuple[str, DemoWorld, Any], browser: Any
) -> None:
    """The page's scripts stop (CDP ``Emulation.setScriptExecutionDisabled``: timers stall as on a
    sleeping tablet, the websocket stays open and the browser still answers the server's pings)
    -> the kernel ends with its chair link; when the scripts run again the page reloads itself.
    (``Page.setWebLifecycleState frozen`` does not stop the timers of a visible headless page.)"""
    from playwright.sync_api import expect

    url, world, voila = served
    port = int(url.rstrip("/").rsplit(":", 1)[1])
    page = _open_live(browser, url)
    expect(page.locator(".pmk-page-pong")).not_to_have_text("0", timeout=60_000)
    first = {p.pid for p in kernels(voila)}
    assert len(first) == 1
    page.evaluate("window.__pmkBeforeSleep = 1")
    cdp = page.context.new_cdp_session(page)
    cdp.send("Emulation.setScriptExecutionDisabled", {"value": True})
    took = wait_until(
        lambda: not kernels(voila) and chair_connections(world.sim.pid, world.ros_port) == 0, GONE_WITHIN, 0.25
    )
    assert took is not None, (
        f"a sleeping page kept {len(kernels(voila))} kernel(s) and "
        f"{chair_connections(world.sim.pid, world.ros_port)} chair connection(s)"
    )
    assert _page_sockets(voila, port) > 0, "the websocket closed: this tested a closed page, not a silent one"
    print(f"\nsleeping page: kernel and chair link gone {took:.1f} s after the page went silent")
    cdp.send("Emulation.setScriptExecutionDisabled", {"value": False})
    page.wait_for_function("window.__pmkBeforeSleep === undefined", timeout=60_000)  # it reloaded itself
    expect(page.locator(".pmk-home-info-state")).to_contain_text("Live", timeout=120_000)
    assert wait_until(lambda: _settled(world, voila, 1), GONE_WITHIN) is not None
    assert {p.pid for p in kernels(voila)}.isdisjoint(first)
