"""Issue 30: the dashboard shows a chair's first SSH host key and sends nothing until it is confirmed.

Real OpenSSH (tests/fixtures_ssh.py) and the simulated chair's map server reading what sshd wrote;
the Maps screen is driven kernel-side, like tests/ui/maps/test_maps.py.
"""

from __future__ import annotations

import base64
import struct
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.ui.common.context import AppContext
from pmk_nb.ui.maps.screen import MapsScreen
from tests.fixtures_ssh import SshdServer, profile_for
from tests.helpers import wait_until
from tests.indoorgml_samples import two_rooms


def _errors(ctx: AppContext) -> list[str]:
    return [n.message for n in ctx.notifications if n.level == "error"]


@pytest.mark.slow
def test_first_host_key_is_shown_and_confirmed_before_any_upload(
    ctx: AppContext, sim_factory: Any, sshd_server: SshdServer, remote_maps_dir: str, tmp_path: Path
) -> None:
    screen = MapsScreen(ctx)
    try:
        screen.import_bytes("house.gml", two_rooms())
        screen.resolution.value = "0.2"
        screen.convert_button.click()
        wait_until(lambda: screen._send_buttons(), what="conversion")
        sim = sim_factory(maps_dir=sshd_server.home, reload_services=("change_map",))
        profile = profile_for(sshd_server, tmp_path, remote_maps_dir, name="chair", host="127.0.0.1", port=sim.port)
        ctx.profiles.save(profile)
        known = Path(profile.known_hosts)
        remote = sshd_server.home / remote_maps_dir.removeprefix("~/")

        screen._send_buttons()[0].click()
        wait_until(lambda: screen.host_key.box.visible or _errors(ctx), what="the host key question")
        shown = screen.host_key.box.message.value
        assert sshd_server.host_key_fingerprint in shown and "First connection" in shown
        assert not known.exists() or sshd_server.host_key_fingerprint not in known.read_text()  # not trusted yet
        assert not remote.exists() and ctx.current_map is None  # nothing was uploaded
        assert "Confirm" in screen.status.value and screen.send_progress.layout.display == "none"

        screen.host_key.box.no.click()  # Cancel: still nothing trusted, nothing sent
        assert not screen.host_key.box.visible and not remote.exists()

        screen._send_buttons()[0].click()
        wait_until(lambda: screen.host_key.box.visible, what="the question again")
        asked = len(_errors(ctx))  # the unknown key is logged (inline: the box says it in the page)
        screen.host_key.box.yes.click()  # "Trust and send"
        wait_until(lambda: ctx.current_map is not None or len(_errors(ctx)) > asked, timeout=60, what="the send")
        assert len(_errors(ctx)) == asked and "Sent" in screen.status.value
        assert (remote / Path(ctx.current_map.yaml).name).is_file()
        key_line = known.read_text()
        assert key_line.startswith(f"[127.0.0.1]:{sshd_server.port} ssh-")

        # a changed key is refused (kept from before): no question, an error
        assert key_line.split()[1] == "ssh-ed25519", key_line
        blob = struct.pack(">I", 11) + b"ssh-ed25519" + struct.pack(">I", 32) + bytes(range(32))
        other = base64.b64encode(blob).decode()
        known.write_text(f"[127.0.0.1]:{sshd_server.port} ssh-ed25519 {other}\n")
        screen._send_buttons()[0].click()
        wait_until(lambda: len(_errors(ctx)) > asked, timeout=60, what="the refusal")
        assert "CHANGED" in _errors(ctx)[-1] and not screen.host_key.box.visible
    finally:
        screen.close()
