"""Pure parsing behind the chair link: odometry, poses, scans, tf, reload codes (stamps and quaternions: tests/wire)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from pmk_nb.chair.link.query import reload
from pmk_nb.chair.link.streams.messages import (
    parse_map_metadata,
    parse_odometry,
    parse_pose,
    parse_scan,
    parse_tf_message,
)
from pmk_nb.viewport import Transform2D
from pmk_nb.wire import quaternion_from_yaw, wrap_angle


def _odom_msg(stamp: dict, yaw: float = 0.3) -> dict:
    return {
        "header": {"stamp": stamp, "frame_id": "/odom"},
        "child_frame_id": "base_link",
        "pose": {"pose": {"position": {"x": 1.5, "y": -2.0, "z": 0.0}, "orientation": quaternion_from_yaw(yaw)}},
        "twist": {"twist": {"linear": {"x": 0.4, "y": 0, "z": 0}, "angular": {"x": 0, "y": 0, "z": -0.2}}},
    }


@pytest.mark.parametrize("stamp", [{"secs": 5, "nsecs": 0}, {"sec": 5, "nanosec": 0}])
def test_parse_odometry_both_flavours(stamp: dict) -> None:
    odom = parse_odometry(_odom_msg(stamp), received=42.0)
    assert (odom.x, odom.y) == (1.5, -2.0)
    assert odom.theta == pytest.approx(0.3)
    assert (odom.v, odom.w) == (0.4, -0.2)
    assert odom.stamp == 5.0
    assert odom.received == 42.0
    assert odom.frame == "odom"  # leading '/' of ROS 1 tf frames dropped


def test_parse_pose_with_covariance_and_plain_pose_stamped() -> None:
    inner = {"position": {"x": 3.0, "y": 4.0, "z": 0}, "orientation": quaternion_from_yaw(-1.0)}
    with_cov = {
        "header": {"frame_id": "map", "stamp": {"sec": 1, "nanosec": 0}},
        "pose": {"pose": inner, "covariance": [0] * 36},
    }
    plain = {"header": {"frame_id": "map", "stamp": {"secs": 1, "nsecs": 0}}, "pose": inner}
    for msg in (with_cov, plain):
        pose = parse_pose(msg, received=1.0)
        assert (pose.x, pose.y, pose.frame) == (3.0, 4.0, "map")
        assert pose.theta == pytest.approx(-1.0)


def test_scan_rays_follow_rep117_and_null_is_unknown() -> None:
    """NaN, +inf, -inf, out of range and null: only +inf is free, null is never free (issue: null rays)."""
    raw = [0.05, 1.0, None, float("nan"), float("inf"), 30.0, 31.0, float("-inf"), 2.5]
    scan = parse_scan({"ranges": raw, "range_min": 0.1, "range_max": 30.0, "angle_increment": 0.1}, received=0.0)
    assert scan.ranges.dtype == np.float32
    assert list(np.isfinite(scan.ranges)) == [False, True, False, False, False, True, False, False, True]
    assert scan.ranges[1] == pytest.approx(1.0) and scan.ranges[8] == pytest.approx(2.5)
    # free up to range_max: +inf only (REP 117); never null, NaN, -inf or a finite value out of range
    assert list(scan.at_max) == [False, False, False, False, True, False, False, False, False]
    assert list(scan.blind) == [True, False, True, True, False, False, True, False, False]
    assert list(scan.too_close) == [False] * 7 + [True, False]


def test_parse_scan_fields_and_angles() -> None:
    msg = {
        "header": {"stamp": {"secs": 2, "nsecs": 0}, "frame_id": "laser"},
        "angle_min": -1.0,
        "angle_max": 1.0,
        "angle_increment": 0.5,
        "range_min": 0.1,
        "range_max": 10.0,
        "ranges": [1.0, 2.0, None, 11.0, 0.01],
    }
    scan = parse_scan(msg, received=9.0)
    assert scan.stamp == 2.0 and scan.received == 9.0
    np.testing.assert_allclose(scan.angles(), [-1.0, -0.5, 0.0, 0.5, 1.0])
    assert np.isnan(scan.ranges[2:]).all()
    assert not scan.at_max.any(), "null and out-of-range readings are not free space"
    assert list(scan.blind) == [False, False, True, True, True]


def test_parse_scan_empty_ranges() -> None:
    scan = parse_scan({"ranges": [], "range_min": 0.1, "range_max": 5.0}, received=0.0)
    assert scan.ranges.size == 0 and scan.at_max.size == 0


def test_map_metadata() -> None:
    info = parse_map_metadata(
        {
            "width": 100,
            "height": 50,
            "resolution": 0.05,
            "origin": {"position": {"x": -1.0, "y": -2.5, "z": 0}, "orientation": {"x": 0, "y": 0, "z": 0, "w": 1}},
        }
    )
    assert (info.width, info.height, info.resolution) == (100, 50, 0.05)
    assert info.origin == (-1.0, -2.5, 0.0)


# -- tf ---------------------------------------------------------------------------------------------
def _tf(parent: str, child: str, x: float, y: float, yaw: float) -> dict:
    return {
        "header": {"frame_id": parent, "stamp": {"sec": 0, "nanosec": 0}},
        "child_frame_id": child,
        "transform": {"translation": {"x": x, "y": y, "z": 0.0}, "rotation": quaternion_from_yaw(yaw)},
    }


@given(
    st.tuples(st.floats(-10, 10), st.floats(-10, 10), st.floats(-3, 3)),
    st.tuples(st.floats(-10, 10), st.floats(-10, 10), st.floats(-3, 3)),
)
def test_transform_compose_inverse(a: tuple, b: tuple) -> None:
    ta, tb = Transform2D(*a), Transform2D(*b)
    ident = ta.compose(ta.inverse())
    assert (ident.x, ident.y) == pytest.approx((0.0, 0.0), abs=1e-9)
    assert wrap_angle(ident.theta) == pytest.approx(0.0, abs=1e-9)
    # composing = applying one after the other to a point
    px, py = ta.compose(tb).apply(1.0, 2.0)
    qx, qy = ta.apply(*tb.apply(1.0, 2.0))
    assert (px, py) == pytest.approx((qx, qy), abs=1e-9)


def test_tf_message_frames_lose_the_ros1_slash() -> None:
    """The link feeds these to ``viewport.TfTree`` (tests/viewport/test_tftree.py): frames as tf2 spells them."""
    (t,) = parse_tf_message({"transforms": [_tf("/map", "/odom", 2.0, 3.0, math.pi / 2)]})
    assert (t.parent, t.child) == ("map", "odom")
    assert (t.x, t.y, t.theta) == pytest.approx((2.0, 3.0, math.pi / 2))
    assert t.stamp == 0.0


# -- reload -----------------------------------------------------------------------------------------
def test_reload_detection_prefers_change_map_then_nav2_then_mapupdate() -> None:
    types = {
        "/change_map": "nav_msgs/LoadMap",
        "/map_server/load_map": "nav2_msgs/srv/LoadMap",
        "/map_update": "pmk_map_server/MapUpdate",
        "/foo/reload": "pmk/MapUpdate",
    }
    everything = list(types)
    assert reload.detect(everything, types.get) == reload.ReloadService("/change_map", "ros1")
    assert reload.detect(everything[1:], types.get) == reload.ReloadService("/map_server/load_map", "nav2")
    assert reload.detect(everything[2:], types.get) == reload.ReloadService("/map_update", "mapupdate")
    # an unusual name is found by its type; a type from rosapi beats the name
    assert reload.detect(["/foo/reload_map"], {"/foo/reload_map": "pmk/MapUpdate"}.get).kind == "mapupdate"
    assert reload.detect(["/change_map"], {"/change_map": "nav2_msgs/srv/LoadMap"}.get).kind == "nav2"
    # no rosapi types: guessed from names
    assert reload.detect(["/chair/map_server/load_map"], lambda _n: None) == reload.ReloadService(
        "/chair/map_server/load_map", "nav2"
    )
    assert reload.detect(["/rosapi/topics"], lambda _n: None) is None


def test_reload_requests_and_codes() -> None:
    assert reload.build_request("ros1", "/m.yaml") == {"map_url": "/m.yaml"}
    assert reload.build_request("nav2", "/m.yaml") == {"map_url": "/m.yaml"}
    assert reload.build_request("mapupdate", "/m.yaml") == {"path": "/m.yaml"}
    nav2 = reload.ReloadService("/map_server/load_map", "nav2")
    reload.check_response(nav2, "/m.yaml", {"result": 0, "map": {}})
    for code, word in (
        (1, "MAP_DOES_NOT_EXIST"),
        (2, "INVALID_MAP_DATA"),
        (3, "INVALID_MAP_METADATA"),
        (255, "UNDEFINED_FAILURE"),
    ):
        with pytest.raises(reload.MapReloadError) as info:
            reload.check_response(nav2, "/m.yaml", {"result": code})
        assert info.value.code == code
        assert word in str(info.value) and "keeps its previous map" in str(info.value)
    ros1 = reload.ReloadService("/change_map", "ros1")
    with pytest.raises(reload.MapReloadError) as info:
        reload.check_response(ros1, "/m.yaml", {"result": 255})
    assert info.value.code == 255
    mu = reload.ReloadService("/map_update", "mapupdate")
    reload.check_response(mu, "/m.yaml", {"done": True})
    with pytest.raises(reload.MapReloadError) as info:
        reload.check_response(mu, "/m.yaml", {"done": False})
    assert info.value.code is None and "/m.yaml" in str(info.value)
