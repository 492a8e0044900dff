"""SimConfig (issue 25): a simulated chair's settings as one value, every default declared once, and the
keyword form of ``SimChair`` kept in step with it."""

from __future__ import annotations

from dataclasses import fields

import pytest

from pmk_nb.defaults import DEFAULT_CHAIR_WIDTH
from pmk_nb.sim.config import SimConfig, SimOptions, field_names
from pmk_nb.sim.server import SimChair, SimError


def test_keyword_options_name_every_config_field_but_the_map() -> None:
    keys = set(SimOptions.__annotations__)
    assert keys == set(field_names()) - {"map_yaml"}
    assert [f.name for f in fields(SimConfig)] == list(field_names())


def test_config_passes_whole_and_keywords_replace_its_fields(tmp_path) -> None:
    config = SimConfig(ros="ros2", odom_rate=25.0, seed=7, maps_dir=tmp_path, nav_actions=False)
    chair = SimChair(config=config)
    assert chair.config == config
    assert (chair.ros, chair.odom_rate, chair.maps_dir) == ("ros2", 25.0, tmp_path)
    assert chair.engine.navigator.offer_actions is False
    again = SimChair(config=config, odom_rate=10.0)  # a keyword replaces one field, the rest stays
    assert (again.ros, again.odom_rate, again.config.seed) == ("ros2", 10.0, 7)
    assert config.odom_rate == 25.0  # the shared config is not changed


def test_keyword_path_builds_the_same_config(tmp_path) -> None:
    chair = SimChair(ros="ros2", scan_rate=5.0, maps_dir=tmp_path)
    assert chair.config == SimConfig(ros="ros2", scan_rate=5.0, maps_dir=tmp_path)
    assert chair.footprint_radius == DEFAULT_CHAIR_WIDTH / 2 == 0.35  # the chair's default width, halved


def test_checks_apply_to_a_config_too() -> None:
    with pytest.raises(SimError):
        SimChair(config=SimConfig(scan_rate=0.0))
    with pytest.raises(SimError):
        SimChair(config=SimConfig(), ros="ros3")  # type: ignore[arg-type]
    with pytest.raises(TypeError):
        SimChair(no_such_option=1)  # type: ignore[call-arg]


def test_a_configured_chair_serves(tmp_path) -> None:
    chair = SimChair(config=SimConfig(host="127.0.0.1", maps_dir=tmp_path)).start()
    try:
        assert chair.running and chair.port > 0
        assert chair.url == f"ws://127.0.0.1:{chair.port}"
    finally:
        chair.stop()
