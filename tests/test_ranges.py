"""REP 117 reading of laser ranges, with JSON null as unknown (pmk_nb.chair.ranges)."""

from __future__ import annotations

import json
import math

import numpy as np

from pmk_nb.chair.ranges import HIT, INVALID, NO_RETURN, TOO_CLOSE, UNKNOWN, blind_ahead, classify_ranges


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
