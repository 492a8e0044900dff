"""A chair link's settings in one value: topics, pose source, staleness, reconnect and ping timing,
TLS, rosbridge authentication. Every default is declared here once; :class:`~pmk_nb.chair.link.client.ChairLink` takes a
``LinkConfig`` whole (``ChairLink(host, port, config)``) and still accepts the same names as
keywords (``ChairLink(host, pose_source="tf")``), the path the notebooks, profiles and tests use.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from pmk_nb.chair.link.streams.hub import PoseSource
    from pmk_nb.chair.link.transport.bridge_auth import BridgeAuth
    from pmk_nb.chair.link.transport.tls import ChairTls


@dataclass(frozen=True)
class LinkConfig:
    """How to talk to one chair (see :class:`~pmk_nb.chair.link.client.ChairLink`)."""

    odom_topic: str = "/odom"
    scan_topic: str = "/scan"
    pose_source: PoseSource = "odometry"
    pose_topic: str | None = None
    stale_after: float = 2.0  # s without a stream message while connected: the link is "stale"
    throttle_ms: dict[str, int] | None = None  # per stream; None: the screen's draw rate decides
    cmd_vel_topic: str = "/cmd_vel"
    goal_topic: str | None = None  # None: the ROS version's default goal topic
    reconnect_initial: float = 0.5
    reconnect_max: float = 10.0
    rosapi_timeout: float = 3.0
    map_topic: str = "/map"
    map_metadata_topic: str = "/map_metadata"
    ping_interval: float | None = None  # None: max(2 s, 2 x stale_after)
    ping_timeout: float | None = None  # None: max(5 s, 2 x stale_after)
    tls: ChairTls | None = None  # wss, trusted as pmk_nb.chair.link.transport.tls says
    auth: BridgeAuth | None = (
        None  # rosbridge's auth op first on every socket (pmk_nb.chair.link.transport.bridge_auth)
    )

    def __post_init__(self) -> None:
        if self.stale_after <= 0:
            raise ValueError(f"stale_after must be > 0 s, got {self.stale_after}")

    def with_options(self, **options: Any) -> LinkConfig:
        """This config with some fields changed; TypeError names an unknown one."""
        unknown = set(options) - {f.name for f in dataclasses.fields(self)}
        if unknown:
            raise TypeError(f"ChairLink got unknown options {sorted(unknown)}")
        return dataclasses.replace(self, **options) if options else self

    @property
    def pings(self) -> tuple[float, float]:
        """(interval, timeout) of the websocket pings that find half-open sockets (chair out of Wi-Fi range)."""
        interval = self.ping_interval if self.ping_interval is not None else max(2.0, 2 * self.stale_after)
        timeout = self.ping_timeout if self.ping_timeout is not None else max(5.0, 2 * self.stale_after)
        return interval, timeout
