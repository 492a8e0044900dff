"""WCAG 2.2 pieces without a browser: contrast maths, the style's colour pairs, the display settings
in the profile and on the app root, and what Home's live regions say (and how urgently)."""

from __future__ import annotations

import math
import time
from pathlib import Path

import ipywidgets as w
import numpy as np
import pytest

from pmk_nb.chair import ChairProfile, Scan
from pmk_nb.errors import SettingsError
from pmk_nb.speech import phrases
from pmk_nb.ui.common.a11y_style import A11Y_CSS, BUTTON_STYLES, CHECKED_PAIRS, FOCUS_PX
from pmk_nb.ui.common.context import AppContext
from pmk_nb.ui.common.contrast import contrast_ratio, parse_hex, relative_luminance
from pmk_nb.ui.common.display_prefs import DisplayPrefs, display_classes
from pmk_nb.ui.common.style import APP_CSS
from pmk_nb.ui.home.live_region import A11Y_SCRIPT, ASSERTIVE_CLASS, POLITE_CLASS, Announcer
from pmk_nb.ui.settings.screen import SettingsScreen


# -- contrast maths ------------------------------------------------------------------------------------
def test_contrast_ratio_matches_the_wcag_reference_values() -> None:
    assert contrast_ratio("#000000", "#ffffff") == pytest.approx(21.0)
    assert contrast_ratio("#fff", "#ffffff") == pytest.approx(1.0)
    assert contrast_ratio("#767676", "#ffffff") == pytest.approx(4.54, abs=0.01)  # the lightest AA grey on white
    assert contrast_ratio("#777777", "#ffffff") < 4.5 < contrast_ratio("#767676", "#ffffff")
    assert contrast_ratio("#6d6d6d", "#eeeeee") == pytest.approx(4.45, abs=0.01)  # axe's number for the tab labels
    assert contrast_ratio("#ffffff", "#388e3c") == pytest.approx(4.11, abs=0.01)  # and for ipywidgets' success
    assert contrast_ratio("#123456", "#abcdef") == contrast_ratio("#abcdef", "#123456")
    assert relative_luminance("#ffffff") == pytest.approx(1.0) and relative_luminance("#000") == 0.0
    assert parse_hex("#0a0") == (0, 170, 0)


@pytest.mark.parametrize("bad", ["red", "#12345", "123456", "#ggg", "rgb(0,0,0)"])
def test_a_colour_that_is_not_hex_is_refused(bad: str) -> None:
    with pytest.raises(ValueError):
        parse_hex(bad)


@pytest.mark.parametrize(("what", "fg", "bg", "minimum"), CHECKED_PAIRS, ids=[p[0] for p in CHECKED_PAIRS])
def test_every_colour_pair_of_the_style_meets_its_minimum(what: str, fg: str, bg: str, minimum: float) -> None:
    assert contrast_ratio(fg, bg) >= minimum, f"{what}: {contrast_ratio(fg, bg):.2f}:1 < {minimum}:1"


def test_the_style_sheet_carries_the_focus_ring_and_the_checked_button_colours() -> None:
    assert A11Y_CSS in APP_CSS
    assert f"outline: {FOCUS_PX}px solid" in A11Y_CSS and ":focus-visible" in A11Y_CSS and FOCUS_PX >= 2
    for name, (bg, fg) in BUTTON_STYLES.items():
        assert f"mod-{name}:hover:enabled {{ background-color: {bg}; color: {fg}; }}" in A11Y_CSS


# -- display settings: profile, Settings screen, app root ----------------------------------------------
def test_display_settings_default_off_and_only_booleans_pass() -> None:
    profile = ChairProfile(name="A", host="127.0.0.1")
    assert (profile.high_contrast, profile.large_text) == (False, False)
    assert ChairProfile.from_dict({"name": "A", "host": "h", "high_contrast": True}).high_contrast is True
    for field in ("high_contrast", "large_text"):
        with pytest.raises(SettingsError) as err:
            ChairProfile.from_dict({"name": "A", "host": "h", field: "yes"})
        assert err.value.field == field


def test_settings_screen_saves_the_display_choices_and_the_app_root_takes_them(ctx: AppContext) -> None:
    root = w.VBox([])
    prefs = DisplayPrefs(root, ctx)
    screen = SettingsScreen(ctx)
    try:
        for key, value in {"name": "Chair A", "host": "127.0.0.1", "ssh_user": "pmk"}.items():
            screen.fields[key].value = value
        screen.fields["high_contrast"].value = "True"
        screen.fields["large_text"].value = "True"
        screen.save_button.click()
        saved = ctx.profiles.get("Chair A")
        assert (saved.high_contrast, saved.large_text) == (True, True)
        # the save's notification re-read the profile: the classes are on without another call
        assert {"pmk-high-contrast", "pmk-large-text"} <= set(root._dom_classes)
        assert SettingsScreen(ctx).fields["high_contrast"].value == "True"  # the form pre-fills it
        screen.fields["high_contrast"].value = "False"
        screen.save_button.click()
        assert "pmk-high-contrast" not in root._dom_classes and "pmk-large-text" in root._dom_classes
    finally:
        prefs.close()
        screen.close()


def test_display_classes_need_a_real_true() -> None:
    assert display_classes(None) == frozenset()

    class Loose:
        high_contrast = "True"  # a string is not a choice
        large_text = True

    assert display_classes(Loose()) == frozenset({"pmk-large-text"})


# -- live regions --------------------------------------------------------------------------------------
def _scan(blind: bool) -> Scan:
    n = 360
    ranges = np.full(n, np.nan if blind else 2.0, dtype=np.float32)
    return Scan(-math.pi, 2 * math.pi / n, 0.1, 8.0, ranges, np.zeros(n, bool), time.monotonic())


def test_goal_news_is_polite_and_a_stop_is_assertive() -> None:
    ann = Announcer()
    assert POLITE_CLASS in ann.polite._dom_classes and ASSERTIVE_CLASS in ann.assertive._dom_classes
    assert "pmk-sr-only" in ann.widget._dom_classes  # read, not shown
    ann.phrase(phrases.arrived("Storage"))
    ann.phrase(phrases.connection_lost())  # the link is said from its states (tick), not twice
    ann.flush()
    assert "Arrived at Storage." in ann.polite.value and ann.assertive.value == ""
    ann.phrase(phrases.stopped("stop button"))
    ann.flush()
    assert "Stopped." in ann.assertive.value
    assert ann.said == [("Arrived at Storage.", "polite"), ("Stopped.", "assertive")]


def test_link_states_and_laser_alerts_are_said_when_they_change() -> None:
    ann = Announcer()
    ann.tick("off")  # the page opening: nothing to say
    assert ann.said == []
    ann.tick("live", _scan(blind=False))
    ann.tick("live", _scan(blind=False))
    assert ann.said == [("Chair connected: live view.", "polite")]
    ann.tick("live", _scan(blind=True))
    ann.tick("live", _scan(blind=True))  # still blind: said once
    assert ann.said[-1] == ("Laser blind ahead.", "assertive") and len(ann.said) == 2
    ann.tick("stale", _scan(blind=True))
    assert ann.said[-1] == ("No data from the chair.", "assertive")
    ann.tick("live", _scan(blind=True))  # blind again after the link came back: said again
    assert ann.said[-2:] == [("Chair connected: live view.", "polite"), ("Laser blind ahead.", "assertive")]


def test_a_burst_keeps_the_newest_and_any_thread_may_say() -> None:
    import threading

    ann = Announcer()
    threads = [threading.Thread(target=ann.say, args=(f"news {i}",)) for i in range(40)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    ann.flush()
    assert len(ann.said) == 1 and ann.said[0][1] == "polite"
    assert ann.polite.value.count("news") <= 2


def test_the_page_script_marks_the_regions_and_frees_the_keyboard() -> None:
    for needed in ("aria-live", '"polite"', '"assertive"', '"status"', '"alert"', "tabindex", '"Tab"'):
        assert needed in A11Y_SCRIPT


def test_home_puts_the_regions_on_the_screen(ctx: AppContext, tmp_path: Path) -> None:
    from pmk_nb.ui.home.screen import HomeScreen

    home = HomeScreen(ctx)
    try:
        assert home.announcer.widget in home.widget.children
        assert home.announcer.phrase in home.rooms.speech.listeners
        home.rooms.speech.say(phrases.arrived("Office"))  # speech off or on, the region hears it
        home.refresh_info()
        assert "Arrived at Office." in home.announcer.polite.value
        home.drive.stop_button.click()
        home.refresh_info()
        assert "Stopped." in home.announcer.assertive.value
    finally:
        home.close()
