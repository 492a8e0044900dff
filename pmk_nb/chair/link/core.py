"""The link's small public core, as the helpers see it: who the chair is, its state and ROS version,
a blocking service call, the open connection for subscribing, and the few publishes a goal needs.

:class:`~pmk_nb.chair.link.client.ChairLink` implements it. The goal routes, the goal watch, the
heartbeat, the side channel, the recorder, the map reader and the connection test take a
:class:`LinkCore`, not a ``ChairLink``: they use public members only and never import ``client``
(which imports them), so the link's modules form no import cycle, not even a type-only one.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

if TYPE_CHECKING:
    from pmk_nb.chair.link.goals.goal import GoalPolicy
    from pmk_nb.chair.link.query.discovery import Discovery
    from pmk_nb.chair.link.streams.messages import MapInfo, Odometry, Pose2D
    from pmk_nb.chair.link.transport.bridge_auth import BridgeAuth
    from pmk_nb.chair.link.transport.ros import LinkRos
    from pmk_nb.chair.link.transport.state import LinkState
    from pmk_nb.chair.link.transport.tls import ChairTls


class LinkCore(Protocol):
    """What a helper may use of a chair link (all public on ``ChairLink``)."""

    host: str
    port: int
    tls: ChairTls | None
    auth: BridgeAuth | None
    rosapi_timeout: float
    discovery: Discovery
    goal_policy: GoalPolicy

    # -- state -------------------------------------------------------------------------------------
    @property
    def state(self) -> LinkState: ...
    @property
    def is_connected(self) -> bool: ...
    @property
    def ros_version(self) -> int | None: ...
    @property
    def ros(self) -> LinkRos | None: ...
    @property
    def config(self) -> dict[str, Any]: ...

    # -- call, subscribe, publish ------------------------------------------------------------------
    def call(self, name: str, type_name: str, args: dict[str, Any], timeout: float | None) -> dict[str, Any]: ...
    def require_ros(self) -> LinkRos: ...
    @property
    def cmd_vel_topic(self) -> str: ...
    @property
    def goal_topic(self) -> str | None: ...
    def publish_cmd_vel(self, v: float, w: float, topic: str | None = None) -> bool: ...
    def send_goal(self, x: float, y: float, theta: float, frame: str = "map") -> bool: ...

    # -- streams and facts -------------------------------------------------------------------------
    def start_streams(self) -> None: ...
    def latest_odom(self) -> Odometry | None: ...
    def latest_pose(self) -> Pose2D | None: ...
    def try_connect(self, timeout: float = 5.0) -> Any: ...
    def map_info(self, timeout: float = 5.0, without_grid: bool = False) -> MapInfo: ...
