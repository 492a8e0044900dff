"""Issue 24: a wss chair in Settings. Test connection shows an unknown certificate's fingerprint and
pins it only on "Trust and connect"; a changed certificate is refused with no trust offered.
Kernel-side ipywidgets like tests/ui/settings/test_settings.py, against the simulator serving TLS."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from pmk_nb.chair.link.transport.tls import pinned
from pmk_nb.errors import ChairCertificateChanged, KioskLocked, UnknownChairCertificate
from pmk_nb.tlscert import file_fingerprint, write_self_signed
from pmk_nb.ui.common.context import AppContext
from pmk_nb.ui.settings.screen import SettingsScreen
from tests.helpers import wait_until
from tests.ui.settings.test_settings import fill


def _tested(screen: SettingsScreen) -> str:
    screen.test_button.click()
    wait_until(lambda: screen.state != "Connecting", timeout=30.0, what="the connection test")
    return screen.state


def test_first_certificate_is_shown_and_pinned_only_when_trusted(
    ctx: AppContext, sim_factory: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("PMK_CONFIG_DIR", str(tmp_path / "cfg"))  # known_hosts and known_certs live here
    cert_a = write_self_signed(tmp_path / "certs", ["127.0.0.1"], stem="a")
    cert_b = write_self_signed(tmp_path / "certs", ["127.0.0.1"], stem="b")
    sim = sim_factory(tls=cert_a)
    screen = SettingsScreen(ctx)
    fill(screen, port=str(sim.port), tls="True")
    screen.save_button.click()
    profile = ctx.profiles.get("Chair A")
    assert profile.tls and profile.bridge_url == f"wss://127.0.0.1:{sim.port}"
    store = profile.known_certs_path
    assert store == tmp_path / "cfg" / "known_certs"

    assert _tested(screen) == "Failed"
    box = screen.cert_prompt.box
    assert box.visible and file_fingerprint(cert_a[0]) in box.message.value
    assert isinstance(screen.last_report.error, UnknownChairCertificate)
    box.no.click()  # Cancel: nothing pinned, still not connected
    assert not box.visible and not store.exists() and screen.state == "Failed"

    assert _tested(screen) == "Failed" and box.visible
    box.yes.click()  # "Trust and connect": pins THAT fingerprint, then tests again
    wait_until(lambda: screen.state == "Connected", timeout=30.0, what="the test after trusting")
    assert pinned(profile.link_options()["tls"], "127.0.0.1", sim.port) == file_fingerprint(cert_a[0])
    assert "<b>" in screen.map_info.value  # the map's facts came over wss

    sim.stop()
    sim.tls = cert_b  # another certificate on the same address
    sim.start()
    assert _tested(screen) == "Failed"
    assert isinstance(screen.last_report.error, ChairCertificateChanged)
    assert not box.visible  # a changed certificate is never offered for trust
    assert "CHANGED" in screen.status.value and file_fingerprint(cert_b[0]) in screen.status.value
    assert pinned(profile.link_options()["tls"], "127.0.0.1", sim.port) == file_fingerprint(cert_a[0])


def test_trusting_a_certificate_needs_the_kiosk_pin(ctx: AppContext, monkeypatch: pytest.MonkeyPatch) -> None:
    """A locked kiosk page cannot pin a certificate, even by calling the action directly."""
    screen = SettingsScreen(ctx)
    unknown = UnknownChairCertificate(
        "first", host="127.0.0.1", port=9, presented="AB:" * 31 + "AB", known_certs=str(ctx.config_dir / "kc")
    )

    def locked(action: str) -> None:
        raise KioskLocked("locked", action=action)

    monkeypatch.setattr(ctx, "require_unlocked", locked)
    assert screen.cert_prompt.ask(unknown, lambda: None)
    with pytest.raises(KioskLocked):
        screen.cert_prompt._trust(unknown, lambda: None)
    assert not (ctx.config_dir / "kc").exists()
