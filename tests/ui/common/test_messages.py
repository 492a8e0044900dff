"""One place per message, cleared by the next action; names for every button (widgets, no browser)."""

from __future__ import annotations

import socket
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import ipywidgets as w
import pytest

from pmk_nb.errors import GridTooLarge, LibraryError
from pmk_nb.ui.app import Dashboard
from pmk_nb.ui.common.context import AppContext
from pmk_nb.ui.common.widgets import button, error_text
from tests.helpers import app_context, wait_until


@pytest.fixture
def app(tmp_path: Path) -> Iterator[Dashboard]:
    with app_context(tmp_path) as context:
        dashboard = Dashboard(context)
        try:
            yield dashboard
        finally:
            dashboard.close()


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _fill(app: Dashboard, port: int) -> None:
    settings = app.screen("settings")
    values = {"name": "Chair A", "host": "127.0.0.1", "port": str(port), "ssh_user": "pmk"}
    for key, value in values.items():
        settings.fields[key].value = value


def _all_widgets(root: w.Widget) -> Iterator[w.Widget]:
    yield root
    for child in getattr(root, "children", ()):
        yield from _all_widgets(child)


def test_a_failure_shown_by_its_screen_is_not_repeated_in_the_app_line(app: Dashboard) -> None:
    ctx: AppContext = app.ctx
    app.show("settings")
    settings = app.screen("settings")
    _fill(app, _closed_port())
    settings.test_button.click()
    wait_until(lambda: settings.state != "Connecting", timeout=30.0, what="the connection test")
    assert settings.state == "Failed" and "pmk-status-reason" in settings.status.value
    assert app.message.value == "", "the failure is in the status: not a second time in the app's line"
    assert any(n.level == "error" and n.inline for n in ctx.notifications)  # still logged


def test_the_app_line_clears_when_the_next_action_reports(app: Dashboard) -> None:
    app.show("maps")
    app.screen("maps").convert_button.click()  # nothing selected: no place on the screen for this
    assert "Select a map" in app.message.value
    app.show("settings")
    _fill(app, 9090)
    app.screen("settings").save_button.click()  # succeeds: the older failure goes
    assert "Saved" in app.screen("settings").message.value
    assert app.message.value == ""


def test_test_connection_never_says_not_saved(app: Dashboard) -> None:
    settings = app.screen("settings")
    _fill(app, 9090)
    settings.fields["port"].value = "ninety"
    settings.save_button.click()
    assert "Not saved" in settings.message.value
    settings.test_button.click()
    assert "Not saved" not in settings.message.value and "Not tested" in settings.message.value
    assert "port number" in settings.errors["port"].value
    assert "port number" not in settings.message.value  # the reason is under its field, once


@pytest.mark.slow
def test_connected_replaces_an_older_connection_failure(app: Dashboard, sim_factory: Any) -> None:
    settings = app.screen("settings")
    app.show("settings")
    _fill(app, _closed_port())
    settings.test_button.click()
    wait_until(lambda: settings.state == "Failed", timeout=30.0, what="the failed test")
    sim = sim_factory()
    settings.fields["port"].value = str(sim.port)
    settings.test_button.click()
    wait_until(lambda: settings.state != "Connecting", timeout=30.0, what="the second test")
    assert settings.state == "Connected"
    assert "Connected" in settings.status.value and "pmk-status-reason" not in settings.status.value
    assert "failed" not in (settings.status.value + app.message.value).lower()


def test_errors_are_worded_for_the_page() -> None:
    big = GridTooLarge("grid too big; use --resolution 0.2", cells=10**9, limit=10**8, suggested_resolution=0.2)
    wrapped = LibraryError("cannot convert map 'x'")
    wrapped.__cause__ = big
    for err in (big, wrapped):
        said = error_text(err, "Converting")
        assert said.startswith("Converting failed:") and "Use 0.2 m per cell" in said and "--" not in said
    assert "unexpectedly (KeyError" in error_text(KeyError("k"), "Saving")


def test_stop_preview_is_not_an_emergency_stop(app: Dashboard) -> None:
    stop = app.screens["home"].disconnect_button
    assert stop.description == "Stop preview" and stop.button_style != "danger" and stop.icon != "stop"


def test_every_button_has_an_accessible_name(app: Dashboard) -> None:
    """A button's name is its text, else its tooltip (the ``title`` attribute)."""
    for name in ("home", "maps", "settings"):
        app.show(name)
        for widget in _all_widgets(app):
            if isinstance(widget, w.Button | w.ToggleButton | w.FileUpload):
                assert (widget.description or "").strip() or (widget.tooltip or "").strip(), widget
    with pytest.raises(ValueError, match="accessible name"):
        button("", "pmk-icon-only", icon="plus")
