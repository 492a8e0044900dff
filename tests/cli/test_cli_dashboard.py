"""Serving rules (token beyond loopback, a taken port is an error), the kiosk PIN store, the page watchdog."""

from __future__ import annotations

import json
import socket
from pathlib import Path

import pytest

from pmk_nb.cli import main
from pmk_nb.errors import SettingsError
from pmk_nb.serve.serving import ServingRefused, check_port_free, check_serving, resolve_token, url_lines
from pmk_nb.serve.voila import write_dashboard_notebook
from pmk_nb.ui.kiosk.pin import LOCKOUT_S, MAX_TRIES, PinStore


def test_beyond_loopback_without_a_token_is_refused_in_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(ServingRefused) as caught:
        check_serving("0.0.0.0", None)
    assert caught.value.reason == "no-token" and "\n" not in str(caught.value)
    check_serving("127.0.0.1", None)  # loopback keeps working without one
    check_serving("0.0.0.0", resolve_token("auto", {}))
    assert main(["dashboard", "--ip", "0.0.0.0", "--port", "8866"]) == 2
    err = capsys.readouterr().err.strip()
    assert "--token" in err and len(err.splitlines()) == 1


def test_the_printed_url_carries_the_token_and_the_config_file_keeps_it_private(tmp_path: Path) -> None:
    token = resolve_token("auto", {})
    assert token and len(token) >= 16 and token != resolve_token("auto", {})
    assert all(f"?token={token}" in line for line in url_lines("0.0.0.0", 8866, token))
    assert url_lines("127.0.0.1", 8866, None) == ["PMK dashboard: http://127.0.0.1:8866/  (Ctrl-C to stop)"]
    write_dashboard_notebook(tmp_path, token=token)
    config = tmp_path / "voila.json"
    assert json.loads(config.read_text())["Voila"]["token"] == token
    assert config.stat().st_mode & 0o077 == 0


def test_a_taken_port_is_a_clear_error() -> None:
    with socket.create_server(("127.0.0.1", 0)) as busy:
        port = busy.getsockname()[1]
        with pytest.raises(ServingRefused) as caught:
            check_port_free("127.0.0.1", port)
    assert caught.value.reason == "port-taken" and caught.value.port == port
    assert "--port" in str(caught.value)


def test_every_command_and_option_has_help(capsys: pytest.CaptureFixture[str]) -> None:
    from pmk_nb.cli import COMMANDS, build_parser

    missing = []
    for name in ("dashboard", "demo"):
        sub = build_parser(name)._subparsers._group_actions[0].choices[name]  # type: ignore[union-attr]
        missing += [f"{name} {a.option_strings or a.dest}" for a in sub._actions if not a.help]
    assert not missing, missing
    assert all(help_text for _module, help_text in COMMANDS.values())


@pytest.mark.slow
def test_the_pin_is_stored_salted_and_hashed_and_checked(tmp_path: Path) -> None:
    now = [0.0]
    pins = PinStore(tmp_path, clock=lambda: now[0])
    assert not pins.is_set()
    with pytest.raises(SettingsError):
        pins.set_pin("12a4", "12a4")
    with pytest.raises(SettingsError):
        pins.set_pin("1234", "1235")
    pins.set_pin("4711", "4711")
    stored = pins.path.read_text()
    assert "4711" not in stored and pins.path.stat().st_mode & 0o077 == 0
    assert pins.check("4711").ok and not pins.check("4712").ok
    PinStore(tmp_path).set_pin("4711", "4711")
    assert pins.path.read_text() != stored  # a new salt each time
    for _ in range(MAX_TRIES - 1):
        assert not pins.check("0000").ok
    assert pins.check("0000").wait_s == LOCKOUT_S
    assert not pins.check("4711").ok  # locked out even with the right PIN
    now[0] += LOCKOUT_S + 1
    assert pins.check("4711").ok
    pins.path.write_text("{not json")
    with pytest.raises(SettingsError):
        pins.check("4711")


def _ticking(watch: object, now: list[float], seconds: float) -> bool:
    """Advance the fake clock ``seconds`` in the watchdog's own 1 s steps, checking at each: True once gone."""
    for _ in range(round(seconds)):
        now[0] += 1.0
        if watch.check():  # type: ignore[attr-defined]
            return True
    return False


def test_the_page_watchdog_closes_the_app_when_pings_stop() -> None:
    from pmk_nb.ui.common.page_lifecycle import FIRST_PING_WITHIN, PAGE_GONE_AFTER, PageWatch

    now = [0.0]
    closed: list[bool] = []
    watch = PageWatch(lambda: closed.append(True), clock=lambda: now[0])
    assert not _ticking(watch, now, 3) and watch.play.playing  # no ping yet: start the page's timer
    watch.play.value = 1  # a ping from the page
    assert watch.pong.value == "1"
    assert not _ticking(watch, now, PAGE_GONE_AFTER - 1) and not closed
    assert _ticking(watch, now, 2) and closed == [True]
    assert watch.check() and closed == [True]  # once
    never = PageWatch(lambda: closed.append(False), clock=lambda: now[0])
    assert _ticking(never, now, FIRST_PING_WITHIN + 1) and closed[-1] is False


def test_a_slow_page_or_a_starved_kernel_is_not_taken_for_gone() -> None:
    """On a loaded server, late pings made kernels end under live pages, which reloaded: a storm."""
    from pmk_nb.ui.common.page_lifecycle import MAX_PAGE_GONE_AFTER, PAGE_GONE_AFTER, PageWatch

    now = [0.0]
    closed: list[str] = []
    watch = PageWatch(lambda: closed.append("slow"), clock=lambda: now[0])
    for k in range(1, 4):  # pings 5 s apart: a slow page, not a gone one
        assert not _ticking(watch, now, 5)
        watch.play.value = k
    assert watch.deadline(now[0]) == 15.0
    assert not _ticking(watch, now, 14) and not closed
    assert _ticking(watch, now, 2) and closed == ["slow"]
    # one huge gap does not stretch the deadline past its cap
    capped = PageWatch(lambda: None, clock=lambda: now[0])
    capped.play.value = 1
    _ticking(capped, now, 1)
    now[0] += 0.5
    capped._on_ping({})
    capped._gaps.append((now[0], 60.0))
    assert capped.deadline(now[0]) == MAX_PAGE_GONE_AFTER
    # the kernel itself held up for 30 s (its pings still queued): that time does not count
    starved = PageWatch(lambda: closed.append("starved"), clock=lambda: now[0])
    starved.play.value = 1
    _ticking(starved, now, 1)
    now[0] += 30.0
    assert not starved.check() and closed == ["slow"]
    assert not _ticking(starved, now, PAGE_GONE_AFTER - 2) and closed == ["slow"]
    assert _ticking(starved, now, 4) and closed == ["slow", "starved"]


def test_a_voila_page_gets_frames_only_after_its_first_heartbeat(monkeypatch: pytest.MonkeyPatch) -> None:
    """Frames drawn before the page's websocket exists would pile up in Voilà's buffer."""
    from pmk_nb.ui.common import page_lifecycle
    from pmk_nb.ui.live.render_loop import RenderLoop

    assert page_lifecycle.page_ready()  # JupyterLab, tests: no page watch, always ready
    watch = page_lifecycle.PageWatch(lambda: None)
    monkeypatch.setattr(page_lifecycle, "_watch", watch)
    drawn: list[int] = []
    loop = RenderLoop(lambda: drawn.append(1))
    loop._tick(loop._stop)
    assert not page_lifecycle.page_ready() and drawn == [] and loop.ticks == 1
    watch.play.value = 1  # the page's first ping
    loop._tick(loop._stop)
    assert page_lifecycle.page_ready() and drawn == [1]


def test_the_page_gone_message_reaches_the_servers_iopub_listener() -> None:
    """What the kernel sends when its page is gone is what the server's manager looks for."""
    from pmk_nb.serve.voila_kernels import PageBoundKernelManager
    from pmk_nb.ui.common.page_lifecycle import PAGE_GONE_MSG, reload_script

    assert PAGE_GONE_MSG == "pmk_page_gone" and hasattr(PageBoundKernelManager, "_listen_for_page_gone")
    script = reload_script()
    for event in ("visibilitychange", "pageshow", "online", "resume"):
        assert f"'{event}'" in script  # waking up is noticed however the browser says it


def test_the_server_collects_page_garbage_after_pages_come_or_go(monkeypatch: pytest.MonkeyPatch) -> None:
    """Cycles left by a page visit are freed at the next reaper pass, not at Python's rare full collection."""
    import gc
    import weakref

    from pmk_nb.serve import voila_kernels
    from pmk_nb.serve.voila_kernels import COLLECT_EVERY, PageBoundKernelManager

    frozen: list[int] = []
    monkeypatch.setattr(voila_kernels.gc, "freeze", lambda: frozen.append(1))  # keep the test process unfrozen
    trims: list[int] = []
    monkeypatch.setattr(voila_kernels, "trim_heap", lambda: trims.append(1) or True)

    class Cycle:
        def __init__(self) -> None:
            self.me = self

    manager = PageBoundKernelManager()
    assert not manager.collect_garbage(100.0), "no page came or went: nothing to collect"
    gc.disable()  # no automatic collection may free it first
    try:
        garbage = Cycle()
        alive = weakref.ref(garbage)
        del garbage
        assert alive() is not None
        manager._churned = True  # what start_kernel, notify_connect/disconnect and a shutdown set
        assert manager.collect_garbage(100.0) and alive() is None and frozen == [1]
        manager._churned = True
        assert not manager.collect_garbage(100.0 + COLLECT_EVERY / 2), "at most one collection per COLLECT_EVERY"
        assert manager.collect_garbage(100.0 + COLLECT_EVERY) and frozen == [1], "frozen once, after the first"
        assert trims == [1, 1], "glibc's heap is trimmed after each collection"
    finally:
        gc.enable()


def test_frames_wait_while_the_page_lags_behind_the_kernels_output() -> None:
    """Flow control: a pong the page has not acked for MAX_BEHIND s means frames are piling up."""
    from pmk_nb.ui.common.page_lifecycle import MAX_BEHIND, PageWatch

    now = [100.0]
    watch = PageWatch(lambda: None, clock=lambda: now[0])
    watch.play.value = 1
    assert watch.behind(now[0]) == 0.0  # a page that never acked (no script yet) is not held back
    watch.ack.value = "1"
    assert watch.acked == 1
    now[0] += 2.0
    watch.play.value = 2  # pong 2 leaves now
    assert watch.behind(now[0] + MAX_BEHIND - 0.1) <= MAX_BEHIND  # still on time
    assert watch.behind(now[0] + MAX_BEHIND + 0.5) > MAX_BEHIND  # the page is behind: no frames
    for bogus in ("abc", "999", "-1", "0", "1"):  # a page can set any value: only a new pong we sent counts
        watch.ack.value = bogus
        assert watch.acked == 1
    watch.ack.value = "2"
    assert watch.acked == 2 and watch.behind(now[0] + 10.0) == 0.0


def test_trimming_the_heap_works_on_this_glibc_machine() -> None:
    from pmk_nb.serve.voila_kernels import trim_heap

    assert trim_heap() is True
