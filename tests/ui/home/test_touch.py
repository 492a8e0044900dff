"""Home for the person in the chair, kernel side (issue 28): rooms picked often, a heading without a
drag, the joystick's side in the profile, the page's size messages checked, the one-line status."""

from __future__ import annotations

import json
import math
from pathlib import Path
from types import SimpleNamespace

import pytest

from pmk_nb.chair import ChairProfile
from pmk_nb.errors import SettingsError
from pmk_nb.ui.goals.heading_buttons import HeadingButtons, heading_of
from pmk_nb.ui.goals.picker import goal_from_pixels
from pmk_nb.ui.home.fit import parse_fit
from pmk_nb.ui.home.statusline import status_line
from pmk_nb.ui.rooms.picks import MAX_RECENT, RoomPicks
from pmk_nb.viewport import Viewport


def test_favourite_and_recent_rooms_come_first_and_survive_a_new_page(tmp_path: Path) -> None:
    picks = RoomPicks(tmp_path)
    rooms = ["Office", "Kitchen", "Storage", "Exam room 1"]
    assert picks.order("floor", rooms) == rooms  # nothing picked yet: the map's order
    picks.remember("floor", "Storage")
    picks.remember("floor", "Kitchen")
    assert picks.toggle_favourite("floor", "Exam room 1") is True
    again = RoomPicks(tmp_path)  # another page, or the kiosk after a restart
    assert again.order("floor", rooms) == ["Exam room 1", "Kitchen", "Storage", "Office"]
    assert again.order("other-floor", rooms) == rooms  # per map
    assert again.toggle_favourite("floor", "Exam room 1") is False
    for i in range(MAX_RECENT + 3):
        again.remember("floor", f"Room {i}")
    assert len(again.recent("floor")) == MAX_RECENT and again.recent("floor")[0] == f"Room {MAX_RECENT + 2}"
    assert again.order("floor", ["Gone"]) == ["Gone"]  # rooms no longer on the map are not offered


def test_a_broken_picks_file_is_a_fresh_start(tmp_path: Path) -> None:
    (tmp_path / "room_picks.json").write_text('{"maps": {"floor": {"recent": [1, null, "Kitchen"]}}}')
    assert RoomPicks(tmp_path).recent("floor") == ["Kitchen"]
    (tmp_path / "room_picks.json").write_text("not json")
    picks = RoomPicks(tmp_path)
    assert picks.recent("floor") == []
    picks.remember("floor", "Office")
    assert json.loads((tmp_path / "room_picks.json").read_text())["maps"]["floor"]["recent"] == ["Office"]


def test_a_heading_chosen_with_a_button_needs_no_drag() -> None:
    view = Viewport(100, 100, 0.1, (0.0, 0.0), 100, 100)
    chosen: list[float | None] = []
    buttons = HeadingButtons(chosen.append)
    buttons.choice.value = "↑"
    assert chosen[-1] == pytest.approx(math.pi / 2)
    tap = goal_from_pixels(view, (50.0, 50.0), (51.0, 50.0), chair=(1.0, 5.0), heading=buttons.heading)
    assert tap is not None and tap[2] == pytest.approx(math.pi / 2)
    # a drag still wins; Auto faces away from the chair as before
    drag = goal_from_pixels(view, (50.0, 50.0), (80.0, 50.0), heading=buttons.heading)
    assert drag is not None and drag[2] == pytest.approx(0.0)
    buttons.reset()
    assert chosen[-1] is None and heading_of("nonsense") is None
    auto = goal_from_pixels(view, (50.0, 50.0), (50.0, 50.0), chair=(1.0, 5.0), heading=buttons.heading)
    assert auto is not None and auto[2] == pytest.approx(0.0)


def test_the_joystick_side_is_kept_in_the_profile() -> None:
    profile = ChairProfile(name="chair", host="127.0.0.1")
    assert profile.drive_hand == "right"
    profile.drive_hand = "left"
    profile.validate()
    assert ChairProfile.from_dict(profile.to_dict()).drive_hand == "left"
    assert ChairProfile.from_dict({"name": "old", "host": "127.0.0.1"}).drive_hand == "right"  # older files
    profile.drive_hand = "middle"
    with pytest.raises(SettingsError):
        profile.validate()


def test_the_drive_panel_docks_at_the_riders_side(tmp_path: Path) -> None:
    from pmk_nb.ui.drive.panel import DrivePanel

    panel = DrivePanel(claims_dir=tmp_path)
    assert "pmk-drive-right" in panel.widget._dom_classes
    assert panel.dock("left") == "left"
    assert "pmk-drive-left" in panel.widget._dom_classes and "pmk-drive-right" not in panel.widget._dom_classes
    assert panel.dock("<script>") == "right"


@pytest.mark.parametrize(
    "text",
    ["", "[]", "nonsense", '{"w": "390", "h": 700}', '{"w": NaN, "h": 700}', '{"w": true, "h": 700}', "x" * 5000],
)
def test_the_pages_size_messages_are_checked(text: str) -> None:
    assert parse_fit(text) is None


def test_a_size_message_is_clamped_and_bad_boxes_dropped() -> None:
    fit = parse_fit(json.dumps({"w": 10, "h": 99999, "boxes": [[1, 2, 3, 4], [1, 2], ["a", 1, 1, 1], [1, 2, 3, 4.5]]}))
    assert fit == (160, 4000, [(1.0, 2.0, 3.0, 4.0), (1.0, 2.0, 3.0, 4.5)])


def test_the_status_line_is_short() -> None:
    odom = SimpleNamespace(v=0.42, w=0.0)
    assert "In Kitchen · 0.42 m/s · Driving" in status_line("live", 0.1, "Kitchen", odom, "Driving")
    assert "Standing" in status_line("live", 0.1, None, SimpleNamespace(v=0.0, w=0.0), None)
    stale = status_line("stale", 7.0, "Kitchen", odom, "Driving")
    assert "No data for 7 s" in stale and "m/s" not in stale and "Driving" not in stale
    assert status_line("live", None, None, None, None) == ""
    assert "&lt;b&gt;" in status_line("live", 0.1, "<b>", None, None)  # room names are escaped


def test_settings_keep_the_joystick_side(tmp_path: Path) -> None:
    from pmk_nb.chair import ProfileStore
    from pmk_nb.library import MapsFolder
    from pmk_nb.ui.common.context import AppContext
    from pmk_nb.ui.settings.screen import SettingsScreen

    ctx = AppContext(MapsFolder(tmp_path / "maps"), ProfileStore(tmp_path / "profiles.json"), config_dir=tmp_path)
    screen = SettingsScreen(ctx)
    screen.load(ChairProfile(name="chair", host="127.0.0.1", drive_hand="left"))
    assert screen.fields["drive_hand"].value == "left"
    assert screen.form_profile().drive_hand == "left"
    screen.fields["drive_hand"].value = "right"
    assert screen.form_profile().drive_hand == "right"
    screen.close()
