"""The planned path as drawn (moved from the link to viewport, issue 25): only the part ahead of the chair."""

from __future__ import annotations

import numpy as np

from pmk_nb.viewport.path import ARRIVED_M, ahead_of


def test_the_path_ahead_starts_at_the_chair_and_ends_empty_on_arrival() -> None:
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]])
    ahead = ahead_of(pts, (1.9, 0.1))
    assert ahead.tolist() == [[1.9, 0.1], [2.0, 0.0], [3.0, 0.0]]
    assert ahead_of(pts, (3.0 - ARRIVED_M / 2, 0.0)).shape == (0, 2)
    assert ahead_of(pts, None).shape == (4, 2)
