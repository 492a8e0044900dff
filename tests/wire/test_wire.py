"""The wire's contract, once: reload answers, type spellings, angles, the deploy's grid hash."""

from __future__ import annotations

import hashlib
import math

import numpy as np
import pytest

from pmk_nb.errors import MapOutsideFolder
from pmk_nb.grid import OccupancyGrid
from pmk_nb.wire import (
    INVALID_MAP_DATA,
    MAP_DOES_NOT_EXIST,
    UNDEFINED_FAILURE,
    empty_request,
    grid_sha256,
    load_failure,
    normalise_type,
    ros1_result,
    wrap_angle,
    yaw_from_quaternion,
)


def test_a_failed_load_answers_with_its_code_and_anything_else_is_undefined() -> None:
    outside = MapOutsideFolder("no", path="/x.pgm", folder="/maps", what="image")
    assert load_failure(outside) == (INVALID_MAP_DATA, str(outside))
    assert load_failure(KeyError("image")) == (UNDEFINED_FAILURE, "KeyError: 'image'")
    assert empty_request("  ") == (MAP_DOES_NOT_EXIST, "empty map url")
    assert empty_request("a.yaml") is None
    assert [ros1_result(c) for c in (0, 1, 3, 255)] == [0, 255, 255, 255]


def test_both_spellings_of_a_type_compare_equal() -> None:
    assert normalise_type("nav_msgs/msg/Odometry") == normalise_type("nav_msgs/Odometry") == "nav_msgs/Odometry"
    assert normalise_type(" /nav2_msgs/srv/LoadMap ") == "nav2_msgs/LoadMap"
    assert normalise_type("nav2_msgs/action/NavigateToPose") == "nav2_msgs/NavigateToPose"
    assert normalise_type("MapUpdate") == "MapUpdate"


@pytest.mark.parametrize("a", [-7.0, -math.pi, -1.0, 0.0, math.pi, 4.0, 13.0])
def test_wrap_angle_lands_in_the_half_open_circle(a: float) -> None:
    w = wrap_angle(a)
    assert -math.pi < w <= math.pi
    assert math.isclose(math.cos(w), math.cos(a), abs_tol=1e-12)
    assert math.isclose(math.sin(w), math.sin(a), abs_tol=1e-12)


def test_a_null_field_is_the_identity_when_read_and_refused_when_strict() -> None:
    q = {"x": None, "y": None, "z": math.sin(0.4), "w": math.cos(0.4)}
    assert yaw_from_quaternion(q) == pytest.approx(0.8)
    assert yaw_from_quaternion({"z": None, "w": None}) == 0.0
    with pytest.raises(TypeError):
        yaw_from_quaternion(q, strict=True)
    assert yaw_from_quaternion({"z": math.sin(0.4), "w": math.cos(0.4)}, strict=True) == pytest.approx(0.8)


def test_the_grid_hash_is_of_the_int8_cells_in_ros_order() -> None:
    data = np.array([[0, 100], [-1, 0]], dtype=np.int8)
    grid = OccupancyGrid(data, 0.05)
    assert grid_sha256(grid) == hashlib.sha256(bytes([0, 100, 255, 0])).hexdigest()
