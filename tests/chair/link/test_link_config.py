"""ChairLink's settings pass through whole as one LinkConfig, defaults declared once (issue 25);
the keyword constructor stays as the compatibility path."""

from __future__ import annotations

import dataclasses
import inspect

import pytest

from pmk_nb.chair.link import ChairLink, LinkConfig


def test_keywords_and_a_whole_config_make_the_same_link() -> None:
    by_name = ChairLink("127.0.0.1", 9, pose_source="tf", stale_after=4.0, goal_topic="/goal", rosapi_timeout=1.5)
    whole = ChairLink(
        "127.0.0.1", 9, LinkConfig(pose_source="tf", stale_after=4.0, goal_topic="/goal", rosapi_timeout=1.5)
    )
    for link in (by_name, whole):
        assert link.link_config == LinkConfig(pose_source="tf", stale_after=4.0, goal_topic="/goal", rosapi_timeout=1.5)
        assert link.config["pose_source"] == "tf" and link.stale_after == 4.0 and link.rosapi_timeout == 1.5
        assert link.goal_topic == "/goal" and link.cmd_vel_topic == "/cmd_vel"
        assert (link.ping_interval, link.ping_timeout) == (8.0, 8.0)  # derived from stale_after: 2x, at least 2 / 5 s
    # keywords on top of a config: the keyword wins, the rest is the config's
    mixed = ChairLink("127.0.0.1", 9, LinkConfig(scan_topic="/scan_front", stale_after=3.0), stale_after=1.0)
    assert mixed.config["scan_topic"] == "/scan_front" and mixed.stale_after == 1.0
    assert (mixed.ping_interval, mixed.ping_timeout) == (2.0, 5.0)


def test_defaults_are_declared_once() -> None:
    """The constructor repeats no default: every setting's default is LinkConfig's."""
    params = inspect.signature(ChairLink.__init__).parameters
    assert list(params) == ["self", "host", "port", "config", "options"]
    link = ChairLink("127.0.0.1")
    assert link.link_config == LinkConfig() and link.port == 9090
    assert {f.name for f in dataclasses.fields(LinkConfig)} >= {"odom_topic", "tls", "ping_timeout", "map_topic"}


def test_unknown_or_impossible_settings_are_refused() -> None:
    with pytest.raises(TypeError, match="odom_topik"):
        ChairLink("127.0.0.1", odom_topik="/odom")
    with pytest.raises(ValueError, match="stale_after"):
        ChairLink("127.0.0.1", stale_after=0)
    with pytest.raises(ValueError, match="stale_after"):
        LinkConfig(stale_after=-1.0)
