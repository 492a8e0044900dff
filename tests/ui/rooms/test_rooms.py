"""Home's rooms by name against the simulated chair on the clinic sample (real link, real widgets):
"You are in", search, Go to a room (arrives inside it), the route drawn, a blocked room named, and
the phrases handed to the page (text for speechSynthesis; espeak-ng WAV when the page cannot speak)."""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
import shapely

from pmk_nb.chair import ChairProfile, ProfileStore
from pmk_nb.library import MapsFolder, convert_plan
from pmk_nb.sim.chair import DriveLimits
from pmk_nb.ui.common.context import AppContext
from pmk_nb.ui.rooms.layer import RoomsOverlay
from pmk_nb.viewport import Viewport
from tests.helpers import wait_ticking

SAMPLE = Path(__file__).resolve().parents[3] / "sample_maps" / "clinic_floor.gml"
START = (15.0, 3.0, 0.0)  # in Exam room 1


@pytest.fixture
def clinic_home(tmp_path: Path, sim_factory: Callable[..., Any]) -> Iterator[tuple[Any, Any, Path]]:
    from pmk_nb.ui.home.screen import HomeScreen

    yaml = convert_plan(SAMPLE, tmp_path / "maps", "clinic", 0.05).maps[0].files.yaml
    sim = sim_factory(map_yaml=yaml, start_pose=START, rays=180, limits=DriveLimits(v_max=1.5, w_max=2.5))
    profiles = ProfileStore(tmp_path / "profiles.json", secrets=False)
    profiles.save(ChairProfile(name="sim", host="127.0.0.1", port=sim.port, speech_rate=1.2))
    ctx = AppContext(MapsFolder(tmp_path / "maps"), profiles, config_dir=tmp_path / "cfg")
    ctx.set_current_map("clinic", yaml, None)
    home = HomeScreen(ctx, canvas_width=320, canvas_height=240, fps=10)
    try:
        yield home, sim, yaml
    finally:
        home.close()
        ctx.close()


@pytest.mark.slow
def test_go_to_a_named_room_arrives_inside_it_and_says_so(clinic_home: Any) -> None:
    home, _sim, _yaml = clinic_home
    rooms = home.rooms
    assert "Exam room 2" in rooms.panel.list.options and "Door Exam room 2" not in rooms.panel.list.options
    rooms.panel.search.value = "exam"
    assert list(rooms.panel.list.options) == ["Exam room 1", "Exam room 2"]
    home.preview_button.click()
    assert wait_ticking(lambda: home.connection_state()[0] == "live", 10.0)
    assert wait_ticking(lambda: "Exam room 1" in home.rooms.panel.here.value, 5.0), rooms.panel.here.value
    assert rooms.speech.rate == 1.2  # from the profile
    rooms.panel.list.value = "Exam room 2"
    rooms.panel.go_button.click()
    assert rooms.route is not None, rooms.panel.status.value
    assert [r.label for r in rooms.route.rooms][2] == "Corridor"  # door to door, through the corridor
    assert rooms.overlay.route and rooms.overlay.goal is not None  # drawn on the map
    assert rooms.panel.cancel_button.layout.display != "none"
    # issue 29 item 9: the destination panel no longer says "No destination" while a Go to… drives
    assert wait_ticking(lambda: "Going to <b>Exam room 2</b>" in home.goal.status.value, 5.0), home.goal.status.value
    assert "No destination" not in home.goal.status.value
    polygon = rooms.rooms.room("Exam room 2").polygon
    link = home.ctx.link()
    assert wait_ticking(lambda: rooms.handle.progress().done, 60.0), rooms.handle.progress()
    assert rooms.handle.progress().status.value == "arrived", rooms.handle.progress()
    pose = link.latest_odom()
    assert shapely.contains_xy(polygon, pose.x, pose.y)
    assert wait_ticking(lambda: "Exam room 2" in rooms.panel.here.value, 3.0)
    assert wait_ticking(lambda: ("Arrived at Exam room 2.", "speech") in rooms.speech.said, 5.0), rooms.speech.said
    assert ("Going to Exam room 2.", "speech") in rooms.speech.said
    assert "Arrived at Exam room 2." in rooms.panel.status.value
    assert rooms.overlay.route == []  # the route leaves the map once there


@pytest.mark.slow
def test_blocked_room_names_the_door_and_the_page_gets_espeak_audio(clinic_home: Any) -> None:
    home, _sim, _yaml = clinic_home
    rooms = home.rooms
    home.preview_button.click()
    assert wait_ticking(lambda: "Exam room 1" in rooms.panel.here.value, 10.0)
    rooms.speech.caps.value = "audio"  # what the page's script says when it has no speechSynthesis
    rooms.chair_width = 1.0  # wider than every door of the clinic
    assert rooms.go("Office") is None
    assert "Door Exam room 1" in rooms.panel.status.value and "Door Office" in rooms.panel.status.value
    assert wait_ticking(lambda: bool(rooms.speech.said), 3.0)
    text, via = rooms.speech.said[-1]
    assert text.startswith("No accessible route to Office.") and via == "audio"
    assert "data:audio/wav;base64," in rooms.speech.say_box.value
    rooms.speech.caps.value = "speech"


@pytest.mark.slow
def test_link_and_stop_phrases(clinic_home: Any) -> None:
    from pmk_nb.drive import StopReason

    home, sim, _yaml = clinic_home
    rooms = home.rooms
    home.preview_button.click()
    assert wait_ticking(lambda: home.connection_state()[0] == "live", 10.0)
    sim.pause()  # the chair goes quiet: the link turns stale
    assert wait_ticking(lambda: ("Connection to the chair lost.", "speech") in rooms.speech.said, 8.0), (
        rooms.speech.said
    )
    sim.resume()
    assert wait_ticking(lambda: ("Connection to the chair restored.", "speech") in rooms.speech.said, 8.0)
    home.drive.on_stop(StopReason.LINK)  # what the drive session calls when it stops the chair
    home.drive.on_stop(StopReason.CLOSED)  # nobody to tell: silent
    assert wait_ticking(lambda: rooms.speech.said[-1][0] == "Stopped, no data from the chair.", 3.0), rooms.speech.said
    time.sleep(1.5)
    assert rooms.speech.said[-1][0] == "Stopped, no data from the chair."


def test_room_names_show_only_where_they_fit() -> None:
    overlay = RoomsOverlay()
    overlay.set_labels([("Exam room 1", 15.0, 3.0, 10.0, 5.9), ("Door Exam room 1", 14.95, 6.0, 0.9, 0.2)])
    whole = Viewport(600, 300, 0.05, (0.0, 0.0), 320, 160)  # the whole 30 m storey in 320 px
    assert [n for n, _, _ in overlay.visible_labels(whole)] == ["Exam room 1"]
    tiny = Viewport(600, 300, 0.05, (0.0, 0.0), 100, 50)
    assert overlay.visible_labels(tiny) == []  # 10 m is 33 px: no room for the name
    v0 = overlay.version
    overlay.set_route([(0.0, 0.0), (1.0, 1.0)], (1.0, 1.0))
    assert overlay.version > v0


def test_speech_settings_are_saved_with_the_profile(tmp_path: Path) -> None:
    from pmk_nb.ui.settings.screen import SettingsScreen
    from tests.helpers import app_context

    with app_context(tmp_path) as ctx:
        screen = SettingsScreen(ctx)
        for key, value in {"name": "Chair A", "host": "127.0.0.1", "port": "9090", "ssh_user": "pmk"}.items():
            screen.fields[key].value = value
        screen.fields["speech_on"].value = "False"
        screen.fields["speech_voice"].value = "en-gb"
        screen.fields["speech_rate"].value = "1,4"
        screen.save_button.click()
        saved = ctx.profiles.get("Chair A")
        assert (saved.speech_on, saved.speech_voice, saved.speech_rate) == (False, "en-gb", 1.4)
        again = SettingsScreen(ctx)
        assert again.fields["speech_on"].value == "False" and again.fields["speech_rate"].value == "1.4"
        screen.fields["speech_rate"].value = "5"
        screen.save_button.click()
        assert "speaking rate" in screen.errors["speech_rate"].value
        assert ctx.profiles.get("Chair A").speech_rate == 1.4  # not saved
