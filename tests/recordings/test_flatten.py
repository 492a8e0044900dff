"""The flattening core (issue 40): a message in any decoder's shape -> one flat row, without pandas."""

from __future__ import annotations

import io
import math

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from mcap_ros2.writer import Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from pmk_nb.chair.link.record.msgdefs import DEFINITIONS
from pmk_nb.chair.link.record.record_convert import to_ros2
from pmk_nb.recordings.flatten import flatten, row, stamp_seconds

ODOM = "nav_msgs/msg/Odometry"


def test_nested_fields_become_dotted_columns_and_sequences_stay_in_one_cell() -> None:
    msg = {
        "header": {"stamp": {"sec": 10, "nanosec": 500_000_000}, "frame_id": "odom"},
        "pose": {"pose": {"position": {"x": 1.5, "y": -2.0, "z": 0.0}}, "covariance": [0.0] * 36},
        "ranges": [1.0, None, 3.0],
        "data": b"\x01\x02",
        "names": ["a", "b"],
        "poses": [{"pose": {"position": {"x": 1.0}}}, {"pose": {"position": {"x": 2.0}}}],
    }
    flat = flatten(msg)
    assert flat["pose.pose.position.x"] == 1.5 and flat["header.frame_id"] == "odom"
    assert isinstance(flat["pose.covariance"], np.ndarray) and flat["pose.covariance"].shape == (36,)
    assert math.isnan(flat["ranges"][1]) and flat["ranges"][2] == 3.0  # a JSON null range is NaN, never 0
    assert flat["data"] == b"\x01\x02" and flat["names"] == ["a", "b"]
    assert flat["poses"] == [{"pose.position.x": 1.0}, {"pose.position.x": 2.0}]
    assert "pose" not in flat and "header" not in flat


def test_decoder_objects_flatten_like_dicts() -> None:
    """mcap_ros2 gives objects with __slots__, rosbags dataclasses with numpy arrays: one row for both."""
    odom = {
        "header": {"stamp": {"sec": 5, "nanosec": 1}, "frame_id": "odom"},
        "child_frame_id": "base_link",
        "pose": {"pose": {"position": {"x": 1.5, "y": 2.5, "z": 0.0}, "orientation": {"w": 1.0}}},
    }
    buf = io.BytesIO()
    writer = Writer(buf)
    schema = writer.register_msgdef(ODOM, DEFINITIONS[ODOM])
    writer.write_message("/odom", schema, to_ros2(odom, ODOM), log_time=1)
    writer.finish()
    buf.seek(0)
    decoded = next(m for *_x, m in make_reader(buf, decoder_factories=[DecoderFactory()]).iter_decoded_messages())
    buf.seek(0)
    raw = next(iter(make_reader(buf).iter_messages()))[2].data
    store = get_typestore(Stores.EMPTY)
    store.register(get_types_from_msg(DEFINITIONS[ODOM], ODOM))
    by_rosbags = flatten(store.deserialize_cdr(raw, ODOM))
    by_mcap = flatten(decoded)
    assert by_mcap["pose.pose.position.y"] == by_rosbags["pose.pose.position.y"] == 2.5
    assert by_mcap["header.stamp.nanosec"] == by_rosbags["header.stamp.nanosec"] == 1
    assert set(by_mcap) == set(by_rosbags) and by_mcap["child_frame_id"] == "base_link"
    assert np.array_equal(by_mcap["pose.covariance"], by_rosbags["pose.covariance"])
    assert "__msgtype__" not in by_rosbags


@pytest.mark.parametrize(
    ("stamp", "seconds"),
    [
        ({"sec": 3, "nanosec": 250_000_000}, 3.25),  # ROS 2
        ({"secs": 3, "nsecs": 250_000_000}, 3.25),  # ROS 1 as rosbridge spells it
        ({"sec": 3, "nsec": 250_000_000}, 3.25),  # Foxglove's JSON schemas
    ],
)
def test_the_stamp_is_read_in_every_spelling(stamp: dict, seconds: float) -> None:
    assert row({"header": {"stamp": stamp}}, 4_000_000_000)["stamp"] == pytest.approx(seconds)


def test_tf_takes_its_first_transform_stamp_and_a_headerless_message_has_nan() -> None:
    tf = {"transforms": [{"header": {"stamp": {"sec": 7, "nanosec": 0}}, "child_frame_id": "base_link"}]}
    assert stamp_seconds(flatten(tf)) == 7.0
    twist = row({"linear": {"x": 0.5}}, 1_500_000_000)
    assert math.isnan(twist["stamp"]) and twist["received"] == 1.5 and twist["linear.x"] == 0.5
    assert list(twist)[:2] == ["received", "stamp"]
