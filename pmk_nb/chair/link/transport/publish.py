"""The topics a link publishes (velocity commands, navigation goals), advertised once per connection.

Nothing is ever queued: without an open connection a command is refused (False), because a motion
command delivered late after a reconnect would move the chair when nobody expects it.
"""

from __future__ import annotations

import time
from typing import Any

import roslibpy

from pmk_nb.wire import make_stamp, quaternion_from_yaw, spell_type

# Where a goal goes when no topic is configured: ROS 1 move_base, Nav2's goal topic.
DEFAULT_GOAL_TOPICS: dict[int, str] = {1: "/move_base_simple/goal", 2: "/goal_pose"}


class Publishers:
    """Advertised ``roslibpy.Topic`` objects of one connection, by topic name."""

    def __init__(self, cmd_vel_topic: str, goal_topic: str | None) -> None:
        self.cmd_vel_topic, self.goal_topic = cmd_vel_topic, goal_topic
        self._topics: dict[str, roslibpy.Topic] = {}

    def reset(self) -> None:
        """Forget the topics of a previous connection (a new ``Ros`` advertises anew)."""
        self._topics = {}

    def unadvertise_all(self) -> None:
        try:
            for topic in self._topics.values():
                topic.unadvertise()
        finally:
            self._topics = {}

    def topic(
        self, ros: roslibpy.Ros | None, name: str, type_name: str, ros_version: int | None
    ) -> roslibpy.Topic | None:
        """The advertised topic ``name`` of this connection (advertised on first use); None when not connected."""
        if ros is None or not ros.is_connected:
            return None
        topic = self._topics.get(name)
        if topic is None:
            topic = roslibpy.Topic(ros, name, spell_type(type_name, ros_version), queue_size=1)
            self._topics[name] = topic
        return topic

    def cmd_vel(
        self, ros: roslibpy.Ros | None, ros_version: int | None, v: float, w: float, name: str | None = None
    ) -> bool:
        """Send one Twist (to ``name``, default the link's ``cmd_vel_topic``); False (nothing sent)
        when not connected."""
        topic = self.topic(ros, name or self.cmd_vel_topic, "geometry_msgs/Twist", ros_version)
        if topic is None:
            return False
        twist = {"linear": {"x": float(v), "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": float(w)}}
        topic.publish(roslibpy.Message(twist))
        return True

    def goal(
        self, ros: roslibpy.Ros | None, ros_version: int | None, x: float, y: float, theta: float, frame: str
    ) -> bool:
        """Publish a PoseStamped goal; False (nothing sent) when not connected or when the ROS version
        is not known yet: a header in the wrong spelling is rejected by the chair's server, silently."""
        if ros_version not in (1, 2):
            return False
        topic = self.topic(
            ros, self.goal_topic or DEFAULT_GOAL_TOPICS[ros_version], "geometry_msgs/PoseStamped", ros_version
        )
        if topic is None:
            return False
        header: dict[str, Any] = {"frame_id": frame, "stamp": make_stamp(time.time(), ros_version)}
        if ros_version == 1:
            header["seq"] = 0
        pose = {"position": {"x": float(x), "y": float(y), "z": 0.0}, "orientation": quaternion_from_yaw(theta)}
        topic.publish(roslibpy.Message({"header": header, "pose": pose}))
        return True
