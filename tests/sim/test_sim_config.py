"""SimConfig (issues 25, 42): a simulated chair's settings as one value, every default declared once; the
chair keeps it whole and reads its settings from it (no keyword copy beside it, no field copied onto it)."""

from __future__ import annotations

from pathlib import Path

import pytest

from pmk_nb.defaults import DEFAULT_CHAIR_WIDTH
from pmk_nb.sim.config import SimConfig, field_names
from pmk_nb.sim.server import SimChair, SimError

#: SimChair attributes named like a SimConfig field: values resolved from it, not copies of it
RESOLVED = {
    "bridge": "the rosbridge server while running (the setting is config.bridge)",
    "maps_dir": "a temporary folder when the config has none",
    "sftp_password": "a random password when the config has none",
    "sftp_port": "the port listened on, once started (the config's may be 0)",
    "tls": "the certificate files as paths, swapped by tests between starts",
}


def test_the_chair_keeps_its_config_and_reads_it(tmp_path: Path) -> None:
    config = SimConfig(ros="ros2", odom_rate=25.0, seed=7, maps_dir=tmp_path, nav_actions=False)
    chair = SimChair(config)
    assert chair.config is config
    assert chair.maps_dir == tmp_path and chair.names.ros == "ros2"
    assert chair.engine.navigator.offer_actions is False
    assert config.footprint_radius == DEFAULT_CHAIR_WIDTH / 2 == 0.35  # the chair's default width, halved
    assert SimChair().config == SimConfig()  # no config: every default


def test_no_config_field_is_copied_onto_the_chair(tmp_path: Path) -> None:
    chair = SimChair(SimConfig(maps_dir=tmp_path))
    copied = set(vars(chair)) & set(field_names())
    assert copied <= set(RESOLVED), (
        f"copied from SimConfig, read chair.config instead: {sorted(copied - set(RESOLVED))}"
    )


def test_a_chair_takes_no_keyword_settings(tmp_path: Path) -> None:
    with pytest.raises(TypeError):
        SimChair(ros="ros2")  # type: ignore[call-arg]
    with pytest.raises(SimError, match="SimConfig"):
        SimChair(tmp_path / "map.yaml")  # type: ignore[arg-type]  # the old positional map: refused, clearly


def test_checks_apply_to_the_config() -> None:
    with pytest.raises(SimError, match="rates"):
        SimChair(SimConfig(scan_rate=0.0))
    with pytest.raises(SimError, match="ROS version"):
        SimChair(SimConfig(ros="ros3"))  # type: ignore[arg-type]
    with pytest.raises(SimError, match="reload service"):
        SimChair(SimConfig(reload_services=("reload_everything",)))
    with pytest.raises(SimError, match="password login off"):
        SimChair(SimConfig(sftp_password_login=False))


def test_a_configured_chair_serves(tmp_path: Path) -> None:
    chair = SimChair(SimConfig(host="127.0.0.1", maps_dir=tmp_path)).start()
    try:
        assert chair.running and chair.port > 0
        assert chair.url == f"ws://127.0.0.1:{chair.port}"
    finally:
        chair.stop()
