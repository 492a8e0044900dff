"""The Home screen's texts and up-front checks, without widgets: info panel lines, preview image, probe."""

from __future__ import annotations

import socket
from pathlib import Path

from pmk_nb.chair import Odometry, Pose2D
from pmk_nb.chair.link import LinkState
from pmk_nb.errors import ChairLinkError
from pmk_nb.ui.common.context import CurrentMap
from pmk_nb.ui.home.checks import preview_image_path, preview_image_problem, probe_chair
from pmk_nb.ui.home.info import (
    NO_VALUE,
    STALE_AFTER,
    STOPPED,
    PreviewSnapshot,
    connection_state,
    info_texts,
    unreachable_text,
    warning_html,
)


def test_connection_states_and_no_data_age() -> None:
    now = 5000.0  # any monotonic reading: the states depend on ages only
    fresh = Odometry(1.0, 2.0, 0.0, 0.5, 0.0, None, now - 0.1)
    old = Odometry(1.0, 2.0, 0.0, 0.5, 0.0, None, now - (STALE_AFTER + 3.0))
    up = LinkState.CONNECTED
    assert connection_state(STOPPED, now) == ("off", None)
    assert connection_state(PreviewSnapshot(up, fresh, fresh, "refused", now), now) == ("unreachable", None)
    assert connection_state(PreviewSnapshot(up, None, None, None, now - 1.0), now) == ("connecting", None)
    state, age = connection_state(PreviewSnapshot(up, None, None, None, now - 60.0), now)
    assert state == "stale" and age is not None and age >= 59  # connected but nothing ever came
    state, age = connection_state(PreviewSnapshot(up, old, old, None, now - 60.0), now)
    assert state == "stale" and age is not None and age > STALE_AFTER
    stale = PreviewSnapshot(LinkState.STALE, fresh, fresh, None, now)
    assert connection_state(stale, now)[0] == "stale"  # the link's own verdict
    assert connection_state(PreviewSnapshot(up, fresh, fresh, None, now), now)[0] == "live"


def test_unreachable_text_names_the_address_once() -> None:
    named = ChairLinkError("Cannot connect to the chair at 10.0.0.5:9090: refused", host="10.0.0.5", port=9090)
    assert unreachable_text(named, "10.0.0.5", 9090) == f"The chair is unreachable: {named}"
    text = unreachable_text(OSError("network is down"), "10.0.0.5", 9090)
    assert text == "The chair at 10.0.0.5:9090 is unreachable: network is down"
    assert unreachable_text(ChairLinkError("rosbridge hung up"), "h", 1).startswith("The chair at h:1 ")
    assert "&lt;b&gt;" in warning_html("<b>") and warning_html("") == ""


def test_info_texts_name_the_position_source_and_the_no_data_state() -> None:
    odom = Odometry(1.234, -5.0, 1.5708, 0.42, -0.1, None, 0.0)
    live = info_texts("live", 0.1, odom, odom, 2, 1.5)
    assert live.position == "x 1.23 m, y -5.00 m, heading 90° (odom frame)"
    assert "0.42 m/s" in live.speed and live.zoom == "Zoom: 2 (x1.5)"
    assert "Live" in live.state and live.status == ""
    in_map = info_texts("live", 0.1, Pose2D(3.0, 4.0, 0.0, "map", 0.0), odom, 1, 1.0)
    assert in_map.position.endswith("(map frame)")
    stale = info_texts("stale", 7.4, odom, odom, 1, 1.0)
    assert "No data for 7 s" in stale.state and "pmk-msg-warning" in stale.state
    assert stale.status is not None and "No data from the chair for 7 s" in stale.status
    assert info_texts("connecting", None, None, None, 1, 1.0).status is None  # leave the page's line alone
    assert info_texts("off", None, None, None, 1, 1.0).position == f"Position: {NO_VALUE}"


def test_stale_values_are_not_shown_as_current() -> None:
    """During a stall the panel never says "No data for 20 s" and "Speed 0.77 m/s" together."""
    odom = Odometry(1.0, 2.0, 0.0, 0.77, 0.1, None, 0.0)
    live = info_texts("live", 0.1, odom, odom, 1, 1.0)
    assert "0.77 m/s" in live.speed and "pmk-stale" not in live.position
    for state in ("stale", "unreachable"):
        texts = info_texts(state, 20.0, odom, odom, 1, 1.0)
        assert "0.77" not in texts.speed and NO_VALUE in texts.speed
        assert "Last known" in texts.position and "pmk-stale" in texts.position


def test_preview_image_check(tmp_path: Path) -> None:
    yaml = tmp_path / "clinic.yaml"
    current = CurrentMap("clinic", yaml, None)
    assert preview_image_path(current) == tmp_path / "clinic-visualization.png"
    problem = preview_image_problem(current)
    assert problem is not None and "clinic-visualization.png" in problem and "Maps screen" in problem
    (tmp_path / "clinic-visualization.png").write_bytes(b"\x89PNG")
    assert preview_image_problem(current) is None
    recorded = CurrentMap("clinic", yaml, tmp_path / "elsewhere.png")  # the path recorded at send time wins
    assert "elsewhere.png" in (preview_image_problem(recorded) or "")


def test_probe_chair_answers_and_refusals() -> None:
    with socket.socket() as server:
        server.bind(("127.0.0.1", 0))
        server.listen(1)
        port = server.getsockname()[1]
        assert probe_chair("127.0.0.1", port, timeout=2.0) is None
    reason = probe_chair("127.0.0.1", port, timeout=2.0)  # closed now
    assert reason and "refused" in reason.lower()
    assert probe_chair("127.0.0.1", 70000, timeout=1.0)  # a hand-edited profile's bad port: a reason, no crash


def test_laser_line_says_blind_ahead_and_touching() -> None:
    """A run of null rays across the heading is summarised as 'laser blind ahead, N°'."""
    import math

    from pmk_nb.chair.link.streams.messages import parse_scan
    from pmk_nb.ui.home.info import laser_text

    def scan(raw: list) -> object:
        return parse_scan(
            {
                "ranges": raw,
                "angle_min": -math.radians(135),
                "angle_increment": math.radians(1),
                "range_min": 0.1,
                "range_max": 30.0,
            },
            received=0.0,
        )

    clear = [2.0] * 271
    assert laser_text(scan(clear)) == "Laser: 271 rays, 0 unknown"
    blind = [2.0] * 125 + [None] * 40 + [2.0] * 106  # -10°..+29° blind
    text = laser_text(scan(blind))
    assert "Laser blind ahead, 40°" in text and "pmk-msg-warning" in text
    behind = [None] * 40 + [2.0] * 231  # blind only behind the chair's right shoulder
    assert laser_text(scan(behind)) == "Laser: 271 rays, 40 unknown"
    touching = [2.0] * 134 + [float("-inf")] * 3 + [2.0] * 134
    assert "touching the chair ahead (3 rays)" in laser_text(scan(touching))
    assert laser_text(None) == ""


def test_heading_and_turn_rate_never_read_minus_zero() -> None:
    """Issue 29 item 9: a chair facing -0.2° showed "heading -0°"; a still chair "turning -0°/s"."""
    odom = Odometry(0.0, 0.0, -0.003, 0.0, -0.001, None, 0.0)
    texts = info_texts("live", 0.1, odom, odom, 1, 1.0)
    assert "heading 0°" in texts.position and "-0" not in texts.position
    assert "turning 0°/s" in texts.speed and "-0" not in texts.speed
    assert "heading -90°" in info_texts("live", 0.1, Odometry(0, 0, -1.5708, 0, 0, None, 0.0), None, 1, 1.0).position
