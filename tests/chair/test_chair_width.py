"""The accessibility check's chair width comes from the chair profile (Settings) unless given."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from pmk_nb.access import profile_chair_width
from pmk_nb.chair.profiles import ChairProfile, ProfileStore
from pmk_nb.errors import SettingsError

SAMPLE = Path("/work/shared/data/indoorgml/fzk_haus_poslist.gml")
if not SAMPLE.is_file():
    SAMPLE = Path(__file__).resolve().parents[3] / "shared" / "data" / "indoorgml" / "fzk_haus_poslist.gml"


def test_profile_has_a_chair_width_checked_for_range() -> None:
    assert ChairProfile("c", "127.0.0.1").chair_width == pytest.approx(0.70)
    for bad in (0.3, 1.6, True):
        with pytest.raises(SettingsError) as err:
            ChairProfile("c", "127.0.0.1", chair_width=bad).validate()
        assert err.value.field == "chair_width"
    ChairProfile("c", "127.0.0.1", chair_width=1.1).validate()


def test_given_width_wins_then_the_profile_then_the_default() -> None:
    wide = ChairProfile("c", "127.0.0.1", chair_width=0.95)
    assert profile_chair_width(0.6, wide) == pytest.approx(0.6)
    assert profile_chair_width(None, wide) == pytest.approx(0.95)
    assert profile_chair_width(None, None) == pytest.approx(0.70)


def _check_json(config: Path, *extra: str) -> dict:
    env = dict(os.environ, PMK_CONFIG_DIR=str(config))
    proc = subprocess.run(
        [sys.executable, "-m", "pmk_nb.cli", "check", str(SAMPLE), "--json", *extra],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
        check=False,
    )
    assert proc.returncode in (0, 1), proc.stderr
    return json.loads(proc.stdout)


@pytest.mark.slow
def test_pmk_check_uses_the_saved_profile_width(tmp_path: Path) -> None:
    assert {s["chair_width"] for s in _check_json(tmp_path)["storeys"]} == {0.7}  # no profile yet
    ProfileStore(tmp_path / "profiles.json", secrets=False).save(ChairProfile("lab", "127.0.0.1", chair_width=1.2))
    assert {s["chair_width"] for s in _check_json(tmp_path)["storeys"]} == {1.2}
    assert {s["chair_width"] for s in _check_json(tmp_path, "--chair-width", "0.8")["storeys"]} == {0.8}


def test_settings_screen_saves_the_chair_width_and_refuses_a_wrong_one(tmp_path: Path) -> None:
    from pmk_nb.ui.settings.screen import SettingsScreen
    from tests.helpers import app_context

    with app_context(tmp_path) as ctx:
        screen = SettingsScreen(ctx)
        for key, value in {"name": "Chair A", "host": "127.0.0.1", "ssh_user": "pmk", "chair_width": "2.5"}.items():
            screen.fields[key].value = value
        screen.save_button.click()
        assert "chair_width" in screen.errors["chair_width"].value and ctx.profiles.names() == []
        screen.fields["chair_width"].value = "0,85"  # a decimal comma is fine
        screen.save_button.click()
        assert ctx.profiles.get("Chair A").chair_width == pytest.approx(0.85)
        assert profile_chair_width(None, ctx.profile()) == pytest.approx(0.85)  # what the Maps screen converts with
        assert SettingsScreen(ctx).fields["chair_width"].value == "0.85"
