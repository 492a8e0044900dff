"""The narrow roles a link plays for the screens that use one: each a Protocol of the few members that
screen calls, so a screen depends on what it uses (and a test hands it a small fake), not on ``ChairLink``.

:class:`~pmk_nb.chair.link.client.ChairLink` implements them all; screens that only read the connection
(its state, the open ``Ros``, rosapi's answers) take :class:`~pmk_nb.chair.link.core.LinkCore`. Nothing in
the link imports this module, so it adds no import cycle, not even a type-only one.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    from pmk_nb.chair.link.goals.goal import GoalHandle
    from pmk_nb.chair.link.query.mapread import MapFacts
    from pmk_nb.chair.link.streams.messages import Pose2D
    from pmk_nb.chair.link.transport.ros import LinkRos
    from pmk_nb.grid import OccupancyGrid
    from pmk_nb.viewport import Transform2D


class GoalLink(Protocol):
    """Sending goals and stopping them (Home's goal panel, the Stop latch)."""

    host: str
    port: int
    goal_gate: Callable[[], float | None] | None

    def navigate_to(
        self, x: float, y: float, yaw: float, frame: str = "map", waypoints: Sequence[tuple[float, float]] = ()
    ) -> GoalHandle: ...
    def stop_goals(self, cmd_vel_topic: str | None = None, *, wait: bool = False) -> list[GoalHandle]: ...
    def running_goals(self) -> list[GoalHandle]: ...


class MapWatchLink(Protocol):
    """The chair's own ``/map`` watched, and the map server's facts (Home's own-map panel)."""

    @property
    def is_connected(self) -> bool: ...
    @property
    def watching_map(self) -> bool: ...
    @property
    def map_problem(self) -> str | None: ...
    def watch_map(self, on: bool = True) -> None: ...
    def latest_map(self) -> tuple[int, OccupancyGrid | None]: ...
    def map_facts(self, timeout: float = 5.0) -> MapFacts | None: ...


class LayerLink(Protocol):
    """The navigation layers' needs: the open connection, topics by type, the pose and tf (the live map)."""

    @property
    def is_connected(self) -> bool: ...
    @property
    def ros(self) -> LinkRos | None: ...
    def latest_pose(self) -> Pose2D | None: ...
    def topics_of_type(self, msg_type: str) -> list[str]: ...
    def frame_transform(self, target: str, source: str) -> Transform2D | None: ...


class PoseLink(Protocol):
    """Setting the chair's initial pose (the live map's tools)."""

    def set_initial_pose(
        self, x: float, y: float, yaw: float, frame: str = "map", topic: str = "/initialpose"
    ) -> bool: ...
