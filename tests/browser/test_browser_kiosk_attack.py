"""A page script attacks a locked kiosk page through the page's own widget manager and kernel connection.

Issue 30, finding 1: the PIN was checked only by the navigation buttons, while every screen's widget
models lived in the kernel from the page's start; a script in the page raised the speed limits and
pressed Save and "Remove PIN" on the hidden Settings screen.  Here the script does that through the
page's widget manager (``window.jupyterapp``, Voilà 0.5 / ipywidgets 8) and also asks the kernel
itself for every live model (``jupyter.widget.control`` / ``request_states``) over the page's own
kernel connection: while locked, no Settings or Maps model exists, and nothing changes on disk.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.chair import PROFILES_FILE, ProfileStore
from pmk_nb.ui.common.context import STATE_FILE
from pmk_nb.ui.kiosk.pin import KIOSK_ENV, PIN_FILE, PinStore
from tests.browser.kiosk_page import VIEWPORT, chromium_page, serve_kiosk

pytestmark = [pytest.mark.slow, pytest.mark.browser, pytest.mark.timeout(300)]

PIN = "4711"
#: Classes of Settings and Maps widgets (the PIN prompt's own widgets are pmk-kiosk-pin, -box, -status)
LOCKED_RE = r"^pmk-(settings|maps|kiosk-pin-(new|repeat|set|remove|section|state|message))"

#: Run in the page: list (and with ``attack``, use) the Settings/Maps models the page's widget manager
#: holds, then ask the kernel for all its live models over the page's own kernel connection.
ATTACK_JS = """async ([attack, lockedRe]) => {
  const locked = new RegExp(lockedRe);
  const manager = await window.jupyterapp.widgetManagerPromise.promise;
  const held = manager._models instanceof Map ? [...manager._models.values()] : Object.values(manager._models);
  const all = (await Promise.all(held.map(p => Promise.resolve(p).catch(() => null)))).filter(m => m);
  const models = all.filter(m => m.comm_live);  // a closed comm carries no message any more
  const classes = m => m.get('_dom_classes') || [];
  const found = models.flatMap(classes).filter(c => locked.test(c));
  const byClass = cls => models.filter(m => classes(m).includes(cls));
  if (attack) {
    for (const m of byClass('pmk-settings-max-linear')) { m.set('value', '2.0'); m.save_changes(); }
    for (const m of byClass('pmk-settings-max-angular')) { m.set('value', '2.0'); m.save_changes(); }
    for (const m of byClass('pmk-settings-save')) m.send({event: 'click'}, {});
    for (const m of byClass('pmk-kiosk-pin-remove')) m.send({event: 'click'}, {});
    for (const m of byClass('pmk-maps-send')) m.send({event: 'click'}, {});
  }
  const listed = await new Promise((resolve, reject) => {
    const comm = manager.kernel.createComm('jupyter.widget.control');
    const timer = setTimeout(() => reject(new Error('the kernel sent no update_states in 20 s')), 20000);
    comm.onMsg = msg => {
      const data = msg.content.data;
      if (data.method !== 'update_states') return;
      clearTimeout(timer);
      resolve(Object.values(data.states));
    };
    comm.open({}, {version: '1.0.0'});
    comm.send({method: 'request_states'}, {});
  });
  const listedClasses = listed.flatMap(s => (s.state && s.state._dom_classes) || []);
  return {found, listed: listedClasses.filter(c => locked.test(c)), kernel: listed.length, managed: models.length,
          stale: all.filter(m => !m.comm_live).flatMap(classes).filter(c => locked.test(c)).length};
}"""


def _files(config: Path, chair_maps: Path) -> dict[str, bytes | None]:
    """The settings a page script went for (profiles, PIN, current map) and the chair's maps folder."""
    names = [config / n for n in (PROFILES_FILE, PIN_FILE, STATE_FILE)] + sorted(chair_maps.rglob("*"))
    return {str(p): p.read_bytes() if p.is_file() else None for p in names}


def _attack(page: Any, attack: bool) -> dict[str, Any]:
    return page.evaluate(ATTACK_JS, [attack, LOCKED_RE])


def test_a_page_script_cannot_reach_settings_or_maps_of_a_locked_kiosk(tmp_path: Path) -> None:
    from playwright.sync_api import expect

    with serve_kiosk(tmp_path, label="kiosk-attack", env={KIOSK_ENV: "1"}) as (url, world):
        PinStore(world.config_dir).set_pin(PIN, PIN)  # before the page (and its kernel) starts
        profiles = world.config_dir / PROFILES_FILE
        before = _files(world.config_dir, world.chair_dir)
        with chromium_page(url, viewport=VIEWPORT) as page:
            expect(page.locator(".pmk-kiosk button.pmk-nav-home")).to_be_visible(timeout=120_000)
            seen = _attack(page, attack=True)
            assert seen["kernel"] > 50 and seen["managed"] > 50, seen  # the kernel and the page did answer
            time.sleep(3.0)  # what a forged Save would have written by now (it takes milliseconds)
            assert _files(world.config_dir, world.chair_dir) == before, "a page script changed settings or maps"
            assert ProfileStore(profiles, secrets=False).last_used().max_linear == 0.5  # type: ignore[union-attr]
            assert PinStore(world.config_dir).is_set(), "a page script removed the PIN"
            assert seen["found"] == [] and seen["listed"] == [], f"Settings/Maps models while locked: {seen}"

            # with the PIN, Settings is built; back Home its models are gone again, from page and kernel
            page.locator("button.pmk-nav-settings").click()
            page.locator(".pmk-kiosk-pin input").fill(PIN)
            page.locator("button.pmk-kiosk-unlock").click()
            expect(page.locator(".pmk-settings-save")).to_be_visible(timeout=30_000)
            assert "pmk-settings-save" in _attack(page, attack=False)["listed"]
            page.locator("button.pmk-nav-home").click()
            expect(page.locator(".pmk-settings-save")).to_have_count(0, timeout=30_000)
            deadline, again = time.monotonic() + 20.0, _attack(page, attack=False)
            while (again["found"] or again["listed"]) and time.monotonic() < deadline:  # the closes in flight
                time.sleep(0.5)
                again = _attack(page, attack=False)
            assert again["found"] == [] and again["listed"] == [], again
