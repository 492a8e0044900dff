"""What the navigation modules need of each other, as Protocols: the engine as the navigator drives it,
and the navigator as its action servers (``navigation_ros1``, ``cancel_service``) use it.

The engine makes the navigator and the navigator makes its servers, so each lower module names the
higher one by the part it uses, declared here, instead of importing it (no cycle, type-only ones
included). :class:`~pmk_nb.sim.engine.Engine` and :class:`~pmk_nb.sim.navigation.Navigator` are
the only implementations.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    from pmk_nb.clock import Clock
    from pmk_nb.sim.chair import Chair, DriveLimits
    from pmk_nb.sim.messages import Names
    from pmk_nb.sim.navgoal import NavGoal
    from pmk_nb.sim.protocol import Bridge
    from pmk_nb.sim.world import World


class PlanningEngine(Protocol):
    """The engine as the navigator sees it: the chair, its world and clocks, and a planner to start or cancel."""

    @property
    def names(self) -> Names: ...

    @property
    def clock(self) -> Clock: ...

    @property
    def wall(self) -> Clock: ...

    @property
    def world(self) -> World | None: ...

    @property
    def chair(self) -> Chair | None: ...

    @property
    def limits(self) -> DriveLimits: ...

    @property
    def paused(self) -> bool: ...

    @property
    def planning(self) -> bool: ...

    def start_plan(
        self, goal: tuple[float, float], yaw: float | None, via: Sequence[tuple[float, float]] = ()
    ) -> None: ...

    def cancel_plan(self) -> None: ...

    def goal_ended(self) -> None: ...

    def note(self, text: str) -> None: ...


class GoalKeeper(Protocol):
    """The navigator as an action server sees it: the one running goal, and checking, starting, cancelling."""

    @property
    def engine(self) -> PlanningEngine: ...

    @property
    def bridge(self) -> Bridge | None: ...

    @property
    def current(self) -> NavGoal | None: ...

    def check(self, target: tuple[float, float, float | None], frame: str) -> str | None: ...

    def start(self, goal: NavGoal) -> None: ...

    def cancel_current(self, why: str = "cancelled") -> None: ...
