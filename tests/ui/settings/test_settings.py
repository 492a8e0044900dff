"""Settings screen driven like a user: fill, save, reload defaults, test connection (sim, closed port)."""

from __future__ import annotations

import json
import socket
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.ui.common.context import AppContext
from pmk_nb.ui.settings.screen import SettingsScreen
from tests.helpers import wait_until


def fill(screen: SettingsScreen, **values: str) -> None:
    base = {"name": "Chair A", "host": "127.0.0.1", "port": "9090", "ssh_user": "pmk"}
    for key, value in {**base, **values}.items():
        screen.fields[key].value = value


def test_save_stores_profile_and_prefills_next_time(ctx: AppContext, tmp_path: Path) -> None:
    screen = SettingsScreen(ctx)
    fill(screen, odom_topic="/wheel_odom", scan_topic="/base_scan", password="hunter2")
    screen.save_button.click()
    assert "Saved" in screen.message.value
    saved = ctx.profiles.get("Chair A")
    assert (saved.odom_topic, saved.scan_topic, saved.port) == ("/wheel_odom", "/base_scan", 9090)
    assert "hunter2" not in (tmp_path / "cfg" / "profiles.json").read_text()
    assert ctx.ssh_password(saved) == "hunter2"
    again = SettingsScreen(ctx)  # the next session starts from the saved values
    assert again.fields["odom_topic"].value == "/wheel_odom"
    assert again.fields["host"].value == "127.0.0.1"
    assert again.fields["password"].value == "" and "stored" in again.fields["password"].placeholder


@pytest.mark.parametrize(
    ("field", "value", "needle"),
    [
        ("port", "ninety", "port number"),
        ("port", "70000", "port number"),
        ("host", "http://chair/", "without scheme"),
        ("odom_topic", "odom", "starts with &#x27;/&#x27;"),
        ("ssh_port", "", "port number"),
        ("name", "a/b", "without slashes"),
    ],
)
def test_invalid_values_are_shown_next_to_the_field(
    ctx: AppContext, tmp_path: Path, field: str, value: str, needle: str
) -> None:
    screen = SettingsScreen(ctx)
    fill(screen, **{field: value})
    screen.save_button.click()
    assert needle in screen.errors[field].value
    assert "Not saved" in screen.message.value
    assert not (tmp_path / "cfg" / "profiles.json").exists()


def test_key_auth_shows_key_field_and_validates_it(ctx: AppContext, tmp_path: Path) -> None:
    screen = SettingsScreen(ctx)
    fill(screen)
    screen.fields["auth"].value = "key"
    assert screen.rows["key_file"].layout.display == "flex" and screen.rows["password"].layout.display == "none"
    screen.fields["key_file"].value = str(tmp_path / "missing_key")
    screen.save_button.click()
    assert "does not exist" in screen.errors["key_file"].value
    key = tmp_path / "id_test"
    key.write_text("not really a key")
    screen.fields["key_file"].value = str(key)
    assert screen.save() is not None and ctx.profiles.get("Chair A").key_file == str(key)


def test_what_goals_do_when_the_dashboard_loses_the_chair(ctx: AppContext) -> None:
    """Issue 24: a Settings control for the link-loss policy, saved in the profile, given to the link."""
    screen = SettingsScreen(ctx)
    fill(screen)
    assert screen.fields["goals_on_link_loss"].value == "finish"  # the default: let goals finish
    screen.fields["goals_on_link_loss"].value = "cancel"
    assert screen.save() is not None
    saved = ctx.profiles.get("Chair A")
    assert saved.goals_on_link_loss == "cancel" and saved.goal_policy().on_link_loss == "cancel"
    assert SettingsScreen(ctx).fields["goals_on_link_loss"].value == "cancel"
    assert ctx.link().goal_policy.on_link_loss == "cancel"
    with pytest.raises(Exception):  # noqa: B017 - traitlets refuses a value outside the options
        screen.fields["goals_on_link_loss"].value = "stop"


def test_a_page_cannot_push_non_text_into_fields(ctx: AppContext) -> None:
    screen = SettingsScreen(ctx)
    fill(screen)
    with pytest.raises(Exception):  # noqa: B017 - traitlets refuses it before our callback sees it
        screen.fields["host"].value = 12  # type: ignore[assignment]
    assert screen.save() is not None


@pytest.mark.slow
def test_connection_to_the_simulator(ctx: AppContext, sim_factory: Any) -> None:
    sim = sim_factory()
    screen = SettingsScreen(ctx)
    fill(screen, port=str(sim.port))
    assert "Disconnected" in screen.status.value
    screen.test_button.click()
    assert screen.state in ("Connecting", "Connected")
    wait_until(lambda: screen.state != "Connecting", timeout=30.0, what="the connection test")
    assert screen.state == "Connected", screen.status.value
    grid = sim.grid
    assert f"<b>{grid.width}</b>" in screen.map_info.value and f"<b>{grid.height}</b>" in screen.map_info.value
    assert f"{grid.resolution:g} m" in screen.map_info.value
    assert "/odom" in screen.fields["odom_topic"].options
    assert "/scan" in screen.fields["scan_topic"].options
    assert screen.info_widget.children == (screen.status, screen.map_info)


def test_connection_to_a_closed_port_shows_the_reason(ctx: AppContext) -> None:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    screen = SettingsScreen(ctx)
    fill(screen, port=str(port))
    screen.test_button.click()
    wait_until(lambda: screen.state != "Connecting", timeout=30.0, what="the connection test")
    assert screen.state == "Failed"
    assert "Disconnected" in screen.status.value
    reason = screen.status.value.split("pmk-status-reason'>", 1)[1]
    assert str(port) in reason or "refused" in reason.lower(), reason
    assert any(n.level == "error" for n in ctx.notifications)
    assert not screen.test_button.disabled  # usable again


def test_profile_picker_switches_between_saved_chairs(ctx: AppContext, tmp_path: Path) -> None:
    screen = SettingsScreen(ctx)
    fill(screen, name="A", host="10.0.0.1")
    screen.save()
    fill(screen, name="B", host="10.0.0.2")
    screen.save()
    assert screen.profile_picker.layout.display == "flex"
    screen.profile_picker.value = "A"
    assert screen.fields["host"].value == "10.0.0.1"
    data = json.loads((tmp_path / "cfg" / "profiles.json").read_text())
    assert data["last_used"] == "B"


def test_settings_says_connected_while_the_page_holds_a_live_link(tmp_path: Path, sim_factory: Any) -> None:
    """Issue 29 item 9: Settings said "Disconnected" while Home was live on the same chair."""
    from pmk_nb.chair import ChairProfile
    from pmk_nb.chair.link import close_all_links
    from pmk_nb.ui import build_app
    from tests.helpers import app_context

    sim = sim_factory()
    with app_context(tmp_path) as ctx:
        ctx.profiles.save(ChairProfile(name="sim", host="127.0.0.1", port=sim.port))
        app = build_app(ctx=ctx)
        try:
            ctx.link().connect(timeout=10.0)  # what Home's preview does
            app.show("settings")
            screen = app.screen("settings")
            assert screen.state == "Connected" and "Disconnected" not in screen.status.value, screen.status.value
            assert "Home" in screen.status.value  # says where the connection comes from
            assert not any("Connected." in n.message for n in ctx.notifications)  # no news: no toast
            close_all_links()
            app.show("home")
            app.show("settings")
            assert app.screen("settings").state == "Disconnected"  # the link is gone: so it says
        finally:
            app.close()
            close_all_links()


def test_saving_a_classroom_seats_profile_keeps_its_chair_secret(ctx: AppContext, tmp_path: Path) -> None:
    """Issue 38: the seat's profile names its chair's rosbridge secret, which the form does not show; a
    student who saves the profile in Settings keeps it (else their own chair would refuse the link)."""
    from pmk_nb.chair import ChairProfile

    screen = SettingsScreen(ctx)
    screen.load(ChairProfile(name="My chair", host="127.0.0.1", bridge_secret_file=str(tmp_path / "secret")))
    screen.fields["cmd_vel_topic"].value = "/other_cmd_vel"
    profile = screen.form_profile()
    assert profile.cmd_vel_topic == "/other_cmd_vel" and profile.bridge_secret_file == str(tmp_path / "secret")
    assert profile.link_options()["auth"].secret_file == tmp_path / "secret"
    screen.close()
