"""A Voilà kernel opens its chair connection only once its page has sent its first heartbeat.

(The soak found kernels whose page closed while loading holding a chair connection until culled.)
"""

from __future__ import annotations

import threading
import time

import pytest

from pmk_nb.clock import VirtualClock
from pmk_nb.ui.home.preview import PreviewController


class _Link:
    host, port = "127.0.0.1", 9090

    def __init__(self) -> None:
        self.connected = threading.Event()
        self.streams = 0

    def on_state_change(self, _cb: object) -> object:
        return lambda: None

    def connect(self, timeout: float) -> None:
        self.connected.set()

    def start_streams(self) -> None:
        self.streams += 1

    def stop_streams(self) -> None:
        pass


def test_the_chair_is_connected_only_after_the_page_is_ready() -> None:
    ready, clock = threading.Event(), VirtualClock()
    ctl = PreviewController(lambda: None, lambda _m: None, ready=ready.is_set, clock=clock)
    link = _Link()
    thread = ctl.start(link)  # type: ignore[arg-type]
    assert clock.wait_for_waiters(1)
    clock.advance(60.0)  # a minute of looks at the page
    assert not link.connected.is_set()  # no page yet: no chair connection
    ready.set()
    clock.advance(0.1)  # the next look
    thread.join(5.0)
    assert link.connected.is_set() and link.streams == 1


def test_a_preview_stopped_before_its_page_came_never_connects() -> None:
    clock = VirtualClock()
    ctl = PreviewController(lambda: None, lambda _m: None, ready=lambda: False, clock=clock)
    link = _Link()
    thread = ctl.start(link)  # type: ignore[arg-type]
    assert clock.wait_for_waiters(1)
    clock.advance(0.2)
    ctl.stop()
    clock.advance(0.1)  # the next look sees the preview stopped
    thread.join(5.0)
    assert not thread.is_alive() and not link.connected.is_set()


def test_a_voila_kernel_counts_its_page_as_unseen_until_the_watch_is_attached(monkeypatch: pytest.MonkeyPatch) -> None:
    """Home starts its preview while the app is built, before the page watch exists."""
    from pmk_nb.ui.common import page_lifecycle

    monkeypatch.setattr(page_lifecycle, "_watch", None)
    monkeypatch.setattr(page_lifecycle, "_LOADED_AT", time.monotonic())  # the kernel has just started
    monkeypatch.setenv(page_lifecycle.PAGE_BOUND_ENV, "1")
    assert not page_lifecycle.page_seen()  # a Voilà page, no watch yet: wait
    monkeypatch.setattr(page_lifecycle, "_LOADED_AT", time.monotonic() - page_lifecycle.UNWATCHED_GRACE - 1)
    assert page_lifecycle.page_seen()  # never attached (a notebook of one's own in Voilà): connect anyway
    monkeypatch.setattr(page_lifecycle, "_LOADED_AT", time.monotonic())
    watch = page_lifecycle.PageWatch(lambda: None)
    monkeypatch.setattr(page_lifecycle, "_watch", watch)
    assert not page_lifecycle.page_seen()
    watch.play.value = 1  # the first heartbeat
    assert page_lifecycle.page_seen()
    monkeypatch.setattr(page_lifecycle, "_watch", None)
    monkeypatch.setenv(page_lifecycle.PAGE_BOUND_ENV, "0")
    assert page_lifecycle.page_seen()  # JupyterLab: the kernel is the notebook's
