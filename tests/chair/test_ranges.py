"""REP 117 reading of laser ranges, with JSON null as unknown (pmk_nb.chair.link.streams.ranges)."""

from __future__ import annotations

import json
import math

import numpy as np

from pmk_nb.chair.link.streams.ranges import HIT, INVALID, NO_RETURN, TOO_CLOSE, UNKNOWN, blind_ahead, classify_ranges


def test_every_reading_gets_its_rep117_meaning_and_null_is_unknown() -> None:
    raw = [1.0, None, math.inf, -math.inf, math.nan, 0.01, 50.0, 9.99]
    ranges, kinds = classify_ranges(raw, 0.05, 10.0)
    assert kinds.tolist() == [HIT, UNKNOWN, NO_RETURN, TOO_CLOSE, INVALID, INVALID, INVALID, HIT]
    assert ranges.dtype == np.float32
    assert ranges[0] == 1.0 and math.isclose(float(ranges[7]), 9.99, rel_tol=1e-6)
    assert np.isnan(ranges[1:7]).all(), "only hits carry a range"


def test_a_rosbridge_json_scan_with_nulls_is_not_free_space() -> None:
    """What rosbridge_suite and rosbridge-server-rs send for NaN and +inf: null."""
    wire = json.loads('{"ranges": [2.5, null, null, null, 3.0], "range_min": 0.1, "range_max": 30.0}')
    _, kinds = classify_ranges(wire["ranges"], wire["range_min"], wire["range_max"])
    assert (kinds == UNKNOWN).sum() == 3
    assert not (kinds == NO_RETURN).any()


def test_python_json_infinity_tokens_keep_their_meaning() -> None:
    wire = json.loads('{"ranges": [Infinity, -Infinity, NaN]}')
    _, kinds = classify_ranges(wire["ranges"], 0.1, 30.0)
    assert kinds.tolist() == [NO_RETURN, TOO_CLOSE, INVALID]


def test_arrays_and_garbage() -> None:
    _, kinds = classify_ranges(np.array([np.inf, 1.0, np.nan], np.float32), 0.1, 5.0)
    assert kinds.tolist() == [NO_RETURN, HIT, INVALID]
    _, kinds = classify_ranges(["x", {}, 1], 0.1, 5.0)
    assert kinds.tolist() == [INVALID, INVALID, HIT]
    ranges, kinds = classify_ranges(None, 0.1, 5.0)
    assert ranges.size == kinds.size == 0


def _scan(n: int = 271) -> np.ndarray:
    return np.radians(np.linspace(-135.0, 135.0, n))  # 1° per ray


def test_blind_sector_ahead_reports_its_whole_width() -> None:
    angles = _scan()
    kinds = np.full(angles.size, HIT, np.uint8)
    ahead = (np.degrees(angles) >= -10) & (np.degrees(angles) < 80)  # 90 rays, crossing 0°
    kinds[ahead] = UNKNOWN
    sector = blind_ahead(kinds, angles)
    assert sector.rays == 90
    assert 89.0 <= sector.degrees <= 91.0


def test_blind_rays_behind_or_beside_do_not_count() -> None:
    angles = _scan()
    kinds = np.full(angles.size, HIT, np.uint8)
    kinds[np.degrees(angles) > 60] = INVALID
    assert blind_ahead(kinds, angles).rays == 0
    # the same rays count when the laser is mounted turned by 90° (chair forward = +90° in its frame)
    assert blind_ahead(kinds, angles, heading_offset=math.radians(90)).rays > 0


def test_too_close_ahead_is_counted() -> None:
    angles = _scan()
    kinds = np.full(angles.size, HIT, np.uint8)
    kinds[135:138] = TOO_CLOSE  # around 0°
    assert blind_ahead(kinds, angles).too_close == 3


def test_a_scan_with_every_kind_of_reading_through_the_simulator_bridge(sim_factory, ros_factory) -> None:
    """NaN, +inf, -inf, out-of-range and normal readings, published to the simulator's rosbridge by
    a plain roslibpy client and read back by the chair link: null on the wire, unknown on screen."""
    import time

    import roslibpy

    from pmk_nb.chair.link.client import ChairLink
    from pmk_nb.ui.home.info import laser_text

    sim = sim_factory()
    pub_ros = ros_factory(sim)
    scan_topic = roslibpy.Topic(pub_ros, "/scan_front", "sensor_msgs/LaserScan")
    scan_topic.advertise()
    n = 271  # 1° per ray, -135°..+135°
    ranges = [2.0] * n
    ranges[125:165] = [math.nan] * 40  # -10°..+29°: blind ahead
    ranges[10], ranges[11], ranges[12] = math.inf, -math.inf, 45.0  # no return, too close, beyond range_max
    msg = {
        "header": {"frame_id": "laser"},
        "angle_min": -math.radians(135),
        "angle_max": math.radians(135),
        "angle_increment": math.radians(1),
        "range_min": 0.1,
        "range_max": 30.0,
        "ranges": ranges,
    }
    with ChairLink("127.0.0.1", sim.port, scan_topic="/scan_front") as link:
        link.connect()
        link.start_streams()
        deadline = time.monotonic() + 10.0
        while link.latest_scan() is None and time.monotonic() < deadline:
            scan_topic.publish(roslibpy.Message(msg))
            time.sleep(0.1)
        scan = link.latest_scan()
    assert scan is not None, "no scan came back through the simulator's bridge"
    kinds = scan.kinds
    assert (kinds[125:165] == UNKNOWN).all(), "NaN travels as null: unknown"
    assert kinds[10] == UNKNOWN and kinds[11] == UNKNOWN, "±inf travel as null too: unknown, not free"
    assert kinds[12] == INVALID and not scan.at_max.any()
    assert (kinds[:10] == HIT).all() and np.isclose(scan.ranges[0], 2.0)
    assert "Laser blind ahead, 40°" in laser_text(scan)
