"""The kiosk lock lives in the kernel (issue 30, finding 1): no Settings or Maps widget exists while a
kiosk page is locked, each of their actions refuses by itself while locked (what a forged or stale
message reaches), and the wrong-PIN lockout is the kiosk's, not the page's."""

from __future__ import annotations

import datetime as dt
import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import ipywidgets as w
import pytest
from ipywidgets.widgets.widget import _instances  # the kernel's registry of live widget models

from pmk_nb.chair import ChairProfile
from pmk_nb.errors import KioskLocked, UnknownHostKey
from pmk_nb.ui import build_app
from pmk_nb.ui.app import Dashboard
from pmk_nb.ui.common.context import AppContext
from pmk_nb.ui.kiosk.mode import KioskGate
from pmk_nb.ui.kiosk.pin import LOCKOUT_S, MAX_LOCKOUT_S, MAX_TRIES, TRIES_FILE, KioskLock, PinCheck, PinStore
from tests.helpers import app_context, wait_until
from tests.indoorgml_samples import two_rooms

PIN = "4711"
#: CSS classes only the Settings and Maps screens' widgets carry (the PIN prompt has its own)
LOCKED_CLASSES = ("pmk-settings", "pmk-maps", "pmk-kiosk-pin-set", "pmk-kiosk-pin-remove", "pmk-kiosk-pin-section")


def _locked_models(since: set[str]) -> list[str]:
    """Classes of live widget models (created after ``since``) that belong to Settings or Maps."""
    found = []
    for model_id, widget in list(_instances.items()):
        if model_id in since:
            continue
        found += [c for c in getattr(widget, "_dom_classes", ()) if c.startswith(LOCKED_CLASSES)]
    return sorted(found)


def _tree(widget: w.Widget) -> list[w.Widget]:
    """Every widget of a tree: children, layouts and styles."""
    out: list[w.Widget] = []
    todo: list[Any] = [widget]
    while todo:
        item = todo.pop()
        if isinstance(item, list | tuple):
            todo.extend(item)
        elif isinstance(item, w.Widget) and all(item is not o for o in out):
            out.append(item)
            todo.extend(getattr(item, name, None) for name in item.keys if name != "comm")
    return out


def _find(widget: w.Widget, css_class: str) -> Any:
    return next(x for x in _tree(widget) if css_class in getattr(x, "_dom_classes", ()))


def _disk(*folders: Path) -> list[tuple[str, int, int]]:
    files = [p for f in folders for p in f.rglob("*") if p.is_file()]
    return sorted((str(p), p.stat().st_size, p.stat().st_mtime_ns) for p in files)


@pytest.fixture
def kiosk_app(tmp_path: Path) -> Iterator[tuple[Dashboard, KioskGate, set[str]]]:
    """A kiosk page (as ``build_app`` makes it on a PMK_KIOSK page) whose PIN is set; the model ids
    that lived before it."""
    PinStore(tmp_path / "cfg").set_pin(PIN, PIN)
    with app_context(tmp_path) as ctx:
        ctx.kiosk = KioskLock(PinStore(ctx.config_dir))
        before = set(_instances)
        app = build_app(ctx=ctx)
        assert isinstance(app, Dashboard) and app.gate is not None
        try:
            yield app, app.gate.__self__, before  # type: ignore[attr-defined]
        finally:
            app.close()


def _unlock(app: Dashboard, gate: KioskGate, screen: str) -> None:
    app.show(screen)
    gate.pin.value = PIN
    assert gate.submit(), gate.status.value
    assert app.current == screen


def test_a_locked_kiosk_has_no_settings_or_maps_widgets_until_the_pin_and_none_after(
    kiosk_app: tuple[Dashboard, KioskGate, set[str]],
) -> None:
    app, gate, before = kiosk_app
    assert set(app.screens) == {"home"} and _locked_models(before) == []
    app.show("settings")  # the prompt only: still nothing of Settings in the kernel
    assert app.content.children == (gate.widget,) and _locked_models(before) == []
    gate.pin.value = "0000"
    assert not gate.submit() and _locked_models(before) == []

    _unlock(app, gate, "settings")
    app.show("maps")
    settings, maps = app.screen("settings"), app.screen("maps")
    live = _locked_models(before)
    assert {"pmk-settings-save", "pmk-kiosk-pin-remove", "pmk-maps-convert", "pmk-maps-download"} <= set(live)

    app.show("home")  # locked again: both screens dropped, every model of theirs closed
    assert set(app.screens) == {"home"} and _locked_models(before) == []
    for screen in (settings, maps):
        assert all(x.comm is None for x in _tree(screen.widget) + _tree(screen.info_widget))
    home = _tree(app.screens["home"].widget) + _tree(app.nav)
    assert home and all(x.comm is not None for x in home), "Home lost widgets it shares with nothing"
    _unlock(app, gate, "maps")  # and built afresh with the PIN
    assert "pmk-maps-convert" in _locked_models(before) and "settings" not in app.screens


def test_every_action_of_a_locked_screen_refuses_by_itself(
    kiosk_app: tuple[Dashboard, KioskGate, set[str]], tmp_path: Path
) -> None:
    """The handlers of screens kept from before the lock, called as a forged message would call them."""
    app, gate, before = kiosk_app
    ctx: AppContext = app.ctx
    ctx.profiles.save(ChairProfile(name="chair", host="127.0.0.1", port=1, ssh_user="pmk"))
    _unlock(app, gate, "maps")
    maps = app.screen("maps")
    maps.import_bytes("house.gml", two_rooms(("F1",)))
    maps.resolution.value = "0.2"
    maps.convert_button.click()
    wait_until(lambda: ctx.maps.entry("house").generated and not maps._files_lock.locked(), what="a conversion")
    gm = ctx.maps.entry("house").generated[0]
    maps.refresh()  # new cards: the replaced ones must not stay live in the kernel either
    send = _find(maps.widget, "pmk-maps-send")
    app.show("settings")
    settings = app.screen("settings")
    app.show("home")
    assert _locked_models(before) == []
    cfg, maps_dir = tmp_path / "cfg", tmp_path / "maps"
    disk, profile_text = _disk(cfg, maps_dir), (cfg / "profiles.json").read_text()
    notes = len(ctx.notifications)

    settings.fields["max_linear"].value = "2.0"
    settings.fields["port"].value = "9"  # loopback only, even if a mutant lets it connect
    settings.save_button.click()
    settings.test_button.click()
    pin_new, pin_repeat = _find(settings.widget, "pmk-kiosk-pin-new"), _find(settings.widget, "pmk-kiosk-pin-repeat")
    pin_new.value, pin_repeat.value = "9999", "9999"
    _find(settings.widget, "pmk-kiosk-pin-set").click()
    _find(settings.widget, "pmk-kiosk-pin-remove").click()
    maps.convert_button.click()
    send.click()
    with pytest.raises(KioskLocked):
        maps.send(gm)
    forged = UnknownHostKey(
        "first key",
        host="127.0.0.1",
        key_type="ssh-ed25519",
        fingerprint="SHA256:x",
        key_base64="AAAA",
        known_hosts=str(cfg / "known_hosts"),
    )
    with pytest.raises(KioskLocked):  # "Trust and send" writes known_hosts
        maps.host_key._trust(forged, lambda: maps.send(gm))
    maps._pending_send, maps.password.value = gm, "hunter2"
    maps.password_ok.click()
    maps.import_confirm.ask("replace?", lambda: maps.import_bytes("house.gml", two_rooms(("F1",), width=9.0)))
    maps.import_confirm.yes.click()
    evil = two_rooms(("F1",), width=7.0)
    maps.upload.value = (
        {
            "name": "evil.gml",
            "type": "",
            "size": len(evil),
            "content": memoryview(evil),
            "last_modified": dt.datetime(2026, 1, 1, tzinfo=dt.UTC),
        },
    )
    maps.downloader.url.value, maps.downloader.name.value = "http://127.0.0.1:9/x.gml", "fetched"
    maps.downloader.button.click()

    refused = [n.message for n in ctx.notifications[notes:] if "kiosk is locked" in n.message]
    assert len(refused) == 10, ctx.notifications[notes:]
    assert refused[0].startswith("Saving settings failed: the kiosk is locked.")
    assert _disk(cfg, maps_dir) == disk and (cfg / "profiles.json").read_text() == profile_text
    assert ctx.profile().max_linear == 0.5 and PinStore(cfg).check(PIN).ok
    assert settings.state == "Disconnected" and ctx.current_map is None
    assert ctx.ssh_password(ctx.profile()) is None  # Send's password box stored nothing


def test_a_pin_set_on_another_page_locks_this_pages_open_settings(tmp_path: Path) -> None:
    """No PIN: Settings is open; once another page sets one, this page's Save refuses (until its PIN)."""
    with app_context(tmp_path) as ctx:
        ctx.kiosk = KioskLock(PinStore(ctx.config_dir))
        app = build_app(ctx=ctx)
        try:
            assert isinstance(app, Dashboard) and set(app.screens) == {"home"}  # the others are built when first opened
            app.show("settings")
            settings = app.screen("settings")
            settings.fields["name"].value, settings.fields["host"].value = "chair", "127.0.0.1"
            PinStore(ctx.config_dir).set_pin(PIN, PIN)  # another page
            settings.save_button.click()
            assert not (tmp_path / "cfg" / "profiles.json").exists()
            assert "kiosk is locked" in ctx.notifications[-1].message
            app.show("home")
            assert set(app.screens) == {"home"}
        finally:
            app.close()


def test_setting_the_first_pin_keeps_this_page_open_until_home(tmp_path: Path) -> None:
    with app_context(tmp_path) as ctx:
        ctx.kiosk = KioskLock(PinStore(ctx.config_dir))
        app = build_app(ctx=ctx)
        try:
            app.show("settings")
            settings = app.screen("settings")
            _find(settings.widget, "pmk-kiosk-pin-new").value = PIN
            _find(settings.widget, "pmk-kiosk-pin-repeat").value = PIN
            _find(settings.widget, "pmk-kiosk-pin-set").click()
            assert PinStore(ctx.config_dir).is_set() and not ctx.kiosk.locked
            settings.fields["name"].value, settings.fields["host"].value = "chair", "127.0.0.1"
            assert settings.save() is not None  # who set the PIN may go on
            app.show("home")
            assert ctx.kiosk.locked and set(app.screens) == {"home"}
        finally:
            app.close()


def test_the_pin_lockout_is_the_kiosks_not_the_pages(tmp_path: Path) -> None:
    """Wrong PINs on one page count on the next (a reload) and on a second page at once; the count is
    kept 0600 in the settings folder; a damaged count locks out (fail closed) for one lockout only."""
    now = [1_000.0]
    PinStore(tmp_path).set_pin(PIN, PIN)
    first, second = (PinStore(tmp_path, clock=lambda: now[0]) for _ in range(2))
    for i in range(MAX_TRIES - 1):
        assert not (first if i % 2 else second).check("0000").ok  # two pages guessing in turn
    assert first.check("0000").wait_s == LOCKOUT_S
    reloaded = PinStore(tmp_path, clock=lambda: now[0])  # a new page: a new store, same folder
    assert reloaded.check(PIN).wait_s > 0 and not reloaded.check(PIN).ok
    tries = tmp_path / TRIES_FILE
    assert tries.stat().st_mode & 0o777 == 0o600 and json.loads(tries.read_text())["locked_until"] > now[0]
    now[0] += LOCKOUT_S + 1
    assert reloaded.check(PIN).ok
    tries.write_text("{damaged")
    assert reloaded.check(PIN).wait_s == LOCKOUT_S  # fail closed ...
    now[0] += LOCKOUT_S + 1
    assert reloaded.check(PIN).ok  # ... for one lockout
    tries.write_text(json.dumps({"failures": 0, "locked_until": now[0] + 10**9, "lockouts": 1}))  # clock went back
    assert reloaded.check(PIN).wait_s == LOCKOUT_S
    now[0] += LOCKOUT_S + 1
    assert reloaded.check(PIN).ok


@pytest.mark.slow
def test_lockouts_in_a_row_double_up_to_a_cap(tmp_path: Path) -> None:
    """A script guessing on and on: 30 s, 60 s, 120 s ... at most MAX_LOCKOUT_S; the right PIN resets it."""
    now = [0.0]
    PinStore(tmp_path).set_pin(PIN, PIN)
    pins = PinStore(tmp_path, clock=lambda: now[0])
    waits = []
    for _ in range(6):  # 30 * 2**5 > MAX_LOCKOUT_S
        for _ in range(MAX_TRIES - 1):
            assert pins.check("0000") == PinCheck(False)
        answer = pins.check("0000")
        waits.append(answer.wait_s)
        now[0] += answer.wait_s + 1
    assert waits[:3] == [LOCKOUT_S, 2 * LOCKOUT_S, 4 * LOCKOUT_S] and waits[-1] == MAX_LOCKOUT_S
    assert pins.check(PIN).ok
    for _ in range(MAX_TRIES):
        answer = pins.check("0000")
    assert answer.wait_s == LOCKOUT_S  # a success ends the row


def test_the_lockout_survives_a_new_app_context(tmp_path: Path) -> None:
    """Through the page: five wrong PINs, then a new page (new kernel state) refuses even the right one."""
    PinStore(tmp_path / "cfg").set_pin(PIN, PIN)
    for attempt in range(2):
        with app_context(tmp_path) as ctx:
            ctx.kiosk = KioskLock(PinStore(ctx.config_dir))
            app = build_app(ctx=ctx)
            try:
                gate: KioskGate = app.gate.__self__  # type: ignore[union-attr]
                app.show("settings")
                if attempt == 0:
                    for _ in range(MAX_TRIES):
                        gate.pin.value = "0000"
                        gate.submit()
                    assert "Too many wrong PINs" in gate.status.value
                else:
                    gate.pin.value = PIN
                    assert not gate.submit() and "Too many wrong PINs" in gate.status.value
                    assert set(app.screens) == {"home"}
            finally:
                app.close()


def test_lock_icons_only_while_a_pin_is_set(tmp_path: Path) -> None:
    """Issue 29 item 9: the demo's kiosk page (no PIN) showed lock icons on Maps and Settings, which
    open freely; the lock shows once a PIN is set, and goes again when it is removed."""
    with app_context(tmp_path) as ctx:
        ctx.kiosk = KioskLock(PinStore(ctx.config_dir))
        app = build_app(ctx=ctx)
        try:
            icons = lambda: {n: app.nav_buttons[n].icon for n in ("maps", "settings")}  # noqa: E731
            assert icons() == {"maps": "map", "settings": "cog"}
            app.show("settings")
            settings = app.screen("settings")
            _find(settings.widget, "pmk-kiosk-pin-new").value = PIN
            _find(settings.widget, "pmk-kiosk-pin-repeat").value = PIN
            _find(settings.widget, "pmk-kiosk-pin-set").click()
            app.show("home")
            assert icons() == {"maps": "lock", "settings": "lock"}
            _unlock(app, app.gate.__self__, "settings")  # type: ignore[union-attr]
            _find(app.screen("settings").widget, "pmk-kiosk-pin-remove").click()
            app.show("home")
            assert icons() == {"maps": "map", "settings": "cog"}
        finally:
            app.close()


def test_the_pin_prompt_is_built_without_deprecated_widget_api(tmp_path: Path) -> None:
    """ipywidgets' ``Text.on_submit`` is deprecated (a DeprecationWarning in the suite): Unlock is the
    one submit path, and the kiosk page's script makes Enter in the PIN box press it."""
    import warnings

    from pmk_nb.ui.kiosk.mode import PIN_ENTER_SCRIPT

    PinStore(tmp_path / "cfg").set_pin(PIN, PIN)
    with app_context(tmp_path) as ctx, warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        ctx.kiosk = KioskLock(PinStore(ctx.config_dir))
        gate = KioskGate(build_app(ctx=ctx), ctx.kiosk)
        assert gate.pin._submission_callbacks.callbacks == []
    assert "button.pmk-kiosk-unlock" in PIN_ENTER_SCRIPT and "'.pmk-kiosk-pin'" in PIN_ENTER_SCRIPT
